#include <cmath>
#include <stdexcept>
#include "support/images.h"

#include <unistd.h>

#include <cstdlib>

namespace isg::test {

io::Image contract_aovs(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const std::vector<std::string> names = {
      "R", "G", "B", "A", "Z", "P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "key.shadow",
      "key.occluder", "key.direct.R", "key.direct.G", "key.direct.B"};
  return make_image(w, h, names, [&](const std::string& n, int x, int y) -> float {
    bool bg = x == 0 && y == 0;  // one background pixel
    bool shadowed = x < w / 2;
    if (n == "A") return bg ? 0.0f : 1.0f;
    if (n == "Z") return bg ? 1e10f : 2.0f + 0.01f * float(y);
    if (n == "key.shadow") return shadowed ? 0.0f : 1.0f;
    if (n == "key.occluder") return shadowed ? 0.5f : 0.0f;
    if (n == "N.Z") return 1.0f;
    if (n == "N.X" || n == "N.Y") return 0.0f;
    if (n == "P.X") return float(x) * 0.01f;
    if (n == "P.Y") return float(y) * 0.01f;
    if (n == "P.Z") return 0.0f;
    return u(rng);
  });
}

std::filesystem::path temp_dir(const std::string& name) {
  const char* base = std::getenv("TMPDIR");
  auto d = std::filesystem::path(base ? base : "/tmp") /
           ("isg-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

ShadowError shadow_error(const io::Image& out, const io::Image& ref, const std::string& light) {
  const auto* mask = ref.find("mask");
  const auto* want = ref.find(light + ".softshadow");
  const auto* soft = out.find(light + ".softshadow");
  const auto* hard = out.find(light + ".shadow");
  if (!mask || !want || !soft || !hard) throw std::runtime_error("shadow_error: missing channels");
  ShadowError e;
  size_t nu = 0;
  for (size_t i = 0; i < mask->data.size(); ++i) {
    if (mask->data[i] <= 0.5f) continue;
    if (want->data[i] < 0.05f) { e.umbra += soft->data[i]; ++nu; }
    e.soft += std::pow(double(soft->data[i]) - want->data[i], 2);
    e.hard += std::pow(double(hard->data[i]) - want->data[i], 2);
    ++e.pixels;
  }
  e.soft = std::sqrt(e.soft / double(e.pixels));
  e.hard = std::sqrt(e.hard / double(e.pixels));
  e.umbra = nu ? e.umbra / double(nu) : 0.0;
  return e;
}

std::filesystem::path shared_case(const std::string& name) {
  auto p = std::filesystem::path(ISG_SHARED_DIR) / "cases" / name;
  return std::filesystem::exists(p / "aovs.exr") ? p : std::filesystem::path();
}

}  // namespace isg::test
