// Small EXR files written by the tests themselves.
#pragma once

#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "io/image.h"

namespace isg::test {

// A w x h image with the named channels filled by `fill(name, x, y)`.
template <class F>
io::Image make_image(int w, int h, const std::vector<std::string>& names, F fill,
                     io::Storage s = io::Storage::f32) {
  io::Image img;
  img.width = img.full_w = w;
  img.height = img.full_h = h;
  for (const auto& n : names) {
    std::vector<float> d(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) d[size_t(y) * w + x] = fill(n, x, y);
    img.channels.push_back({n, s, std::move(d)});
  }
  return img;
}

// A contract-named AOV image with one light `key`: a lit/shadowed split with random values.
io::Image contract_aovs(int w, int h, unsigned seed = 1);

// A fresh empty folder under the test temp dir.
std::filesystem::path temp_dir(const std::string& name);

// ../shared/cases/<name>, or empty when ../shared is absent (tests then GTEST_SKIP).
std::filesystem::path shared_case(const std::string& name);

// A run's soft shadow against a reference, over the reference's `mask`: RMSE of `L.softshadow`
// (the effect) and of `L.shadow` (doing nothing) against the reference's `L.softshadow`, and the
// mean of `L.softshadow` where the reference is in umbra (below 0.05).
struct ShadowError {
  double soft = 0, hard = 0, umbra = 0;
  size_t pixels = 0;
};
ShadowError shadow_error(const io::Image& out, const io::Image& ref, const std::string& light = "key");

}  // namespace isg::test
