#include "metrics/compare.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isg::metrics {

namespace {

// Separable gaussian blur (11 taps, sigma 1.5) with clamped edges, in double.
std::vector<double> blur(const std::vector<double>& src, int w, int h) {
  constexpr int R = 5;
  double k[2 * R + 1], sum = 0;
  for (int i = -R; i <= R; ++i) sum += k[i + R] = std::exp(-0.5 * i * i / (1.5 * 1.5));
  for (double& v : k) v /= sum;
  std::vector<double> tmp(src.size()), out(src.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -R; i <= R; ++i) s += k[i + R] * src[size_t(y) * w + std::clamp(x + i, 0, w - 1)];
      tmp[size_t(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -R; i <= R; ++i) s += k[i + R] * tmp[size_t(std::clamp(y + i, 0, h - 1)) * w + x];
      out[size_t(y) * w + x] = s;
    }
  return out;
}

double psnr_of(double mse) {
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

}  // namespace

Metrics compare_planes(const std::vector<float>& a, const std::vector<float>& b, int w, int h,
                       const std::vector<float>& mask, const std::string& name) {
  const size_t n = size_t(w) * size_t(h);
  Metrics m;
  m.channel = name;
  double se = 0, ae = 0;
  std::vector<double> da(n), db(n), aa(n), bb(n), ab(n);
  for (size_t i = 0; i < n; ++i) {
    da[i] = a[i];
    db[i] = b[i];
    aa[i] = da[i] * da[i];
    bb[i] = db[i] * db[i];
    ab[i] = da[i] * db[i];
    if (!mask.empty() && !(mask[i] > 0.5f)) continue;
    double d = da[i] - db[i];
    se += d * d;
    ae += std::abs(d);
    m.max_abs = std::max(m.max_abs, std::abs(d));
    ++m.pixels;
  }
  if (m.pixels == 0) return m;
  m.rmse = std::sqrt(se / double(m.pixels));
  m.mean_abs = ae / double(m.pixels);
  m.psnr = psnr_of(se / double(m.pixels));
  auto ma = blur(da, w, h), mb = blur(db, w, h), saa = blur(aa, w, h), sbb = blur(bb, w, h),
       sab = blur(ab, w, h);
  const double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  double ssum = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!mask.empty() && !(mask[i] > 0.5f)) continue;
    double va = saa[i] - ma[i] * ma[i], vb = sbb[i] - mb[i] * mb[i], cov = sab[i] - ma[i] * mb[i];
    ssum += ((2 * ma[i] * mb[i] + C1) * (2 * cov + C2)) /
            ((ma[i] * ma[i] + mb[i] * mb[i] + C1) * (va + vb + C2));
  }
  m.ssim = ssum / double(m.pixels);
  return m;
}

Comparison compare(const io::Image& a, const io::Image& b, std::vector<std::string> channels,
                   const std::vector<float>& mask) {
  if (a.width != b.width || a.height != b.height) {
    throw io::IoError(b.path.string() + ": size " + std::to_string(b.width) + "x" +
                      std::to_string(b.height) + " differs from " + a.path.string() + " (" +
                      std::to_string(a.width) + "x" + std::to_string(a.height) + ")");
  }
  if (channels.empty()) {
    for (const auto& c : a.channels)
      if (b.find(c.name) && c.name != "mask") channels.push_back(c.name);
    if (channels.empty()) {
      throw io::IoError(a.path.string() + " and " + b.path.string() + " share no channel names");
    }
  }
  Comparison r;
  r.all.channel = "all";
  double se = 0, ae = 0, ssim = 0;
  for (const auto& name : channels) {
    const io::Channel* ca = a.find(name);
    const io::Channel* cb = b.find(name);
    if (!ca) throw io::IoError(a.path.string() + ": no channel " + name);
    if (!cb) throw io::IoError(b.path.string() + ": no channel " + name);
    Metrics m = compare_planes(ca->data, cb->data, a.width, a.height, mask, name);
    se += m.rmse * m.rmse * double(m.pixels);
    ae += m.mean_abs * double(m.pixels);
    ssim += m.ssim;
    r.all.pixels += m.pixels;
    r.all.max_abs = std::max(r.all.max_abs, m.max_abs);
    r.channels.push_back(m);
  }
  if (r.all.pixels) {
    r.all.rmse = std::sqrt(se / double(r.all.pixels));
    r.all.mean_abs = ae / double(r.all.pixels);
    r.all.psnr = psnr_of(se / double(r.all.pixels));
    r.all.ssim = ssim / double(channels.size());
  }
  r.all.pixels /= channels.size();
  return r;
}

}  // namespace isg::metrics

namespace isg::metrics {

namespace {
// A few stops of a magma-like ramp; linear in between.
void ramp(double t, unsigned char* out) {
  static const double stops[][3] = {{0, 0, 4},       {59, 15, 112},   {140, 41, 129},
                                    {222, 73, 104},  {254, 159, 109}, {252, 253, 191}};
  t = std::clamp(t, 0.0, 1.0) * 5.0;
  int i = std::min(int(t), 4);
  double f = t - i;
  for (int c = 0; c < 3; ++c) out[c] = (unsigned char)std::lround(stops[i][c] * (1 - f) + stops[i + 1][c] * f);
}
}  // namespace

Heatmap heatmap(const io::Image& a, const io::Image& b, const std::vector<std::string>& channels,
                const std::vector<float>& mask, double max_error) {
  if (a.width != b.width || a.height != b.height) throw io::IoError(b.path.string() + ": size differs from " + a.path.string());
  const size_t n = a.pixels();
  std::vector<double> err(n, 0.0);
  for (const auto& name : channels) {
    const io::Channel* ca = a.find(name);
    const io::Channel* cb = b.find(name);
    if (!ca) throw io::IoError(a.path.string() + ": no channel " + name);
    if (!cb) throw io::IoError(b.path.string() + ": no channel " + name);
    for (size_t i = 0; i < n; ++i) err[i] += std::abs(double(ca->data[i]) - double(cb->data[i])) / double(channels.size());
  }
  Heatmap h;
  h.width = a.width;
  h.height = a.height;
  h.max_error = max_error;
  if (h.max_error <= 0) {
    std::vector<double> in;
    for (size_t i = 0; i < n; ++i)
      if (mask.empty() || mask[i] > 0.5f) in.push_back(err[i]);
    if (!in.empty()) {
      size_t k = std::min(in.size() - 1, size_t(0.99 * double(in.size())));
      std::nth_element(in.begin(), in.begin() + long(k), in.end());
      h.max_error = in[k];
    }
    if (h.max_error <= 0) h.max_error = 1e-6;
  }
  h.rgb.resize(3 * n);
  for (size_t i = 0; i < n; ++i) {
    unsigned char* px = h.rgb.data() + 3 * i;
    if (!mask.empty() && !(mask[i] > 0.5f)) {
      px[0] = px[1] = px[2] = 96;
      continue;
    }
    ramp(err[i] / h.max_error, px);
  }
  return h;
}

}  // namespace isg::metrics
