// Runs a shell command for the CLI tests, capturing its exit status, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace isg::test {

struct CommandResult {
  int code = -1;  // the exit status, or -1 when the command did not exit normally
  std::string out, err;
};

inline CommandResult run_command(const std::string& cmd) {
  static int k = 0;
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(k++);
  const auto o = dir / ("isg-cmd-out-" + tag), e = dir / ("isg-cmd-err-" + tag);
  const int rc = std::system((cmd + " >" + o.string() + " 2>" + e.string() + " </dev/null").c_str());
  CommandResult r;
  r.code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::stringstream so, se;
  so << std::ifstream(o).rdbuf();
  se << std::ifstream(e).rdbuf();
  r.out = so.str();
  r.err = se.str();
  std::filesystem::remove(o);
  std::filesystem::remove(e);
  return r;
}

}  // namespace isg::test
