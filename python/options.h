// The options of `isg run` that shape a job, as the Python module takes them, and the job
// (lib/run/job.h) they make: the same parameter table, presets, overrides and role mapping as
// the CLI.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "run/job.h"

namespace isg::python {

struct Options {
  std::string scene;                            // scene file (JSON); empty: none
  std::string preset;                           // a shipped preset's name or a TOML file
  std::vector<std::string> sets;                // "section.key=value", as --set
  std::map<std::string, std::string> channels;  // role -> channel name, as --channel
  std::string layer;                            // Blender view layer
  std::string compression;                      // output.compression
  std::string input_colorspace;
  bool no_clobber = false;
};

// Throws params::ParamError (preset, --set) or io::IoError (scene, channels) naming the file or
// key.
run::JobConfig make_job(const Options& o);

}  // namespace isg::python
