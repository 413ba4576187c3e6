#include "run/install.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

// Set by lib/CMakeLists.txt: the build folder, the source tree's presets and the build's
// isg-exrcheck, used only by binaries that run from that build folder.
#ifndef ISG_BUILD_DIR
#define ISG_BUILD_DIR ""
#endif
#ifndef ISG_SOURCE_PRESETS
#define ISG_SOURCE_PRESETS ""
#endif
#ifndef ISG_BUILD_EXRCHECK
#define ISG_BUILD_EXRCHECK ""
#endif

namespace isg::run {

namespace fs = std::filesystem;

namespace {

bool under(const fs::path& file, const fs::path& dir) {
  if (dir.empty()) return false;
  std::error_code ec;
  fs::path f = fs::weakly_canonical(file, ec), d = fs::weakly_canonical(dir, ec);
  if (ec) return false;
  auto [end, _] = std::mismatch(d.begin(), d.end(), f.begin(), f.end());
  return end == d.end();
}

}  // namespace

Layout layout_of(const fs::path& self, const fs::path& to_prefix) {
  Layout l;
  l.self = self;
  std::error_code ec;
  l.prefix = fs::weakly_canonical(self.parent_path() / to_prefix, ec);
  if (ec) l.prefix = (self.parent_path() / to_prefix).lexically_normal();
  l.in_build_tree = under(self, ISG_BUILD_DIR);
  if (const char* env = std::getenv("ISG_PRESET_PATH")) {
    std::stringstream ss(env);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) l.preset_dirs.emplace_back(d);
  }
  if (!l.in_build_tree) l.preset_dirs.push_back(l.prefix / "share" / "isg" / "presets");
  if (l.in_build_tree && !std::string(ISG_SOURCE_PRESETS).empty()) l.preset_dirs.emplace_back(ISG_SOURCE_PRESETS);
  // Always a path, found or not: where it is missing, reading says so (limits.check_seconds)
  // rather than decoding in-process without the child's protection.
  if (const char* env = std::getenv("ISG_EXRCHECK"); env && *env) {
    l.exrcheck = env;
  } else {
    l.exrcheck = l.in_build_tree ? fs::path(ISG_BUILD_EXRCHECK) : l.prefix / "bin" / "isg-exrcheck";
  }
  return l;
}

Layout executable_layout() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return Layout{};
  return layout_of(exe, "..");
}

fs::path object_file_of(const void* address) {
  Dl_info info{};
  if (dladdr(address, &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  fs::path p = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path(info.dli_fname) : p;
}

}  // namespace isg::run
