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

std::filesystem::path shared_case(const std::string& name) {
  auto p = std::filesystem::path(ISG_SHARED_DIR) / "cases" / name;
  return std::filesystem::exists(p / "aovs.exr") ? p : std::filesystem::path();
}

}  // namespace isg::test
