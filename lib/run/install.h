// Where an isg binary finds what it ships with (issue 55): its presets and the isg-exrcheck
// helper that decodes pixels. An installed binary looks beside the prefix it was installed
// into and nowhere else; a binary in its build tree also looks in the source tree's presets/.
// One rule for the CLI and the Python module, each passing its own file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace isg::run {

struct Layout {
  std::filesystem::path self;      // the executable or the Python module's shared object
  std::filesystem::path prefix;    // the install prefix it sits in (`self`'s bin/.. and so on)
  bool in_build_tree = false;      // `self` is under the build folder it was built in
  std::vector<std::filesystem::path> preset_dirs;  // $ISG_PRESET_PATH, prefix/share/isg/presets, source presets/ (build tree only)
  std::filesystem::path exrcheck;  // $ISG_EXRCHECK, else prefix/bin/isg-exrcheck (the build's in the build tree), found or not
};

// `self` is the binary's file; `to_prefix` the relative path from its folder to the install
// prefix ("..": bin/isg; the Python module's is set at configure time).
Layout layout_of(const std::filesystem::path& self, const std::filesystem::path& to_prefix);

// The running executable's layout (/proc/self/exe, one level below the prefix).
Layout executable_layout();

// The file of the loaded object (executable or shared object) that holds `address` (dladdr).
std::filesystem::path object_file_of(const void* address);

}  // namespace isg::run
