// Image error metrics for `isg compare`, the tests and the benchmark.
#pragma once

#include <string>
#include <vector>

#include "io/image.h"

namespace isg::metrics {

struct Metrics {
  std::string channel;  // "all" for the pooled row
  size_t pixels = 0;    // pixels counted (inside the mask)
  double rmse = 0, psnr = 0, mean_abs = 0, max_abs = 0, ssim = 0;
};

// Per-channel metrics for planes a and b (w*h each), over pixels where mask > 0.5 (all if
// mask is empty). PSNR uses peak 1; SSIM a gaussian 11x11 window, sigma 1.5, L = 1.
Metrics compare_planes(const std::vector<float>& a, const std::vector<float>& b, int w, int h,
                       const std::vector<float>& mask, const std::string& name);

struct Comparison {
  std::vector<Metrics> channels;
  Metrics all;  // pooled over channels (SSIM averaged)
};

// Compares the named channels (all channels both have, when `channels` is empty).
Comparison compare(const io::Image& a, const io::Image& b, std::vector<std::string> channels,
                   const std::vector<float>& mask);

}  // namespace isg::metrics

namespace isg::metrics {

// An error heat-map: per pixel, the mean over `channels` of |a − b|, mapped through a
// perceptual ramp (black → purple → orange → yellow) from 0 to `max_error` (≤ 0: the 99th
// percentile of the error). Pixels outside the mask are grey. Returns 8-bit RGB, and the scale.
struct Heatmap {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  double max_error = 0;
};
Heatmap heatmap(const io::Image& a, const io::Image& b, const std::vector<std::string>& channels,
                const std::vector<float>& mask, double max_error);

}  // namespace isg::metrics
