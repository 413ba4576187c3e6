// `isg farm submit` and `isg farm status`: frame ranges as Slurm array jobs (lib/farm).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace isg::cli {

class FarmCommand {
 public:
  // Adds the `farm` subcommand and its own subcommands to `app`.
  explicit FarmCommand(CLI::App& app);
  bool parsed() const { return farm_->parsed(); }
  int run() const;  // exit status of docs/farm.md

 private:
  int submit() const;
  int status() const;

  CLI::App* farm_ = nullptr;
  CLI::App* submit_ = nullptr;
  CLI::App* status_ = nullptr;
  struct Submit {
    std::string input, output, frames, log_dir, job_name = "isg", partition, isg;
    std::vector<std::string> sbatch_args;
    int chunk = 10, max_parallel = 0;
    double poll = 1.0;
    bool skip_existing = false, wait = false, dry_run = false;
    // Passed on to `isg run`.
    std::string scene, preset, layer, compression, device, input_colorspace;
    std::vector<std::string> sets, channels;
    bool require_gpu = false;
  } s_;
  std::string status_dir_;
  bool status_json_ = false;
};

}  // namespace isg::cli
