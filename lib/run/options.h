// The options that shape a job, as `isg run`/`isg info` and the Python module take them, and the
// one assembly of a job from them (issue 56): parameters (defaults, preset, overrides), the
// scene, the role request and the read limits.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "run/install.h"
#include "run/job.h"

namespace isg::run {

struct JobOptions {
  std::string scene;                                        // scene file; empty: none
  std::string preset;                                       // a shipped preset's name or a TOML file
  std::vector<std::string> sets;                            // "section.key=value"
  std::vector<std::pair<std::string, std::string>> channels;  // role -> channel name
  std::string layer;                                        // Blender view layer
  std::string compression;                                  // output.compression; empty: the preset's
  std::string input_colorspace;                             // empty: scene-linear
  bool no_clobber = false;
  // How errors and provenance name the options: the CLI's flags, or Python's keywords.
  std::string set_label = "--set", channel_label = "--channel", compression_label = "--compression";
};

// Defaults, then the preset (looked up in layout.preset_dirs), then compression, then the sets.
// Throws params::ParamError naming the preset, key or set.
params::Params job_params(const JobOptions& o, const Layout& layout);

// The job: parameters, scene (read), role request (the scene's lights, [channels], the
// channel options), read limits (isg-exrcheck from the layout) and write options. Throws
// ParamError or io::IoError naming the file, key or option.
JobConfig make_job(const JobOptions& o, const Layout& layout, const std::string& version);

// The read limits the [limits] parameters give, decoding in layout.exrcheck's child.
io::ReadLimits read_limits(const params::Params& p, const Layout& layout);

}  // namespace isg::run
