// `isg farm`: parsing and printing; the work is in lib/farm.
#include "farm.h"

#include <filesystem>
#include <fstream>
#include <iostream>

#include "farm/farm.h"
#include "io/image.h"
#include "io/scene.h"
#include "frames/frames.h"
#include "run/job.h"

namespace isg::cli {

namespace fs = std::filesystem;

FarmCommand::FarmCommand(CLI::App& app) {
  farm_ = app.add_subcommand("farm", "frame ranges on a Slurm farm (docs/farm.md)");
  farm_->require_subcommand(1);

  submit_ = farm_->add_subcommand("submit",
                                  "submit a frame range as a Slurm array job, one chunk a task");
  auto* c = submit_;
  c->add_option("input", s_.input, "input frame pattern (#### or %04d)")->required();
  c->add_option("-o,--output", s_.output, "output frame pattern")->required();
  c->add_option("--frames", s_.frames, "frame range: A-B, A-BxSTEP or a list")->required();
  c->add_option("--chunk", s_.chunk, "frames per task")->capture_default_str();
  c->add_option("--max-parallel", s_.max_parallel,
                "tasks running at once (the array's %N; 0: no limit)");
  c->add_flag(
      "--skip-existing", s_.skip_existing,
      "leave frames whose output exists (not submitted; tasks skip them too): cheap retries");
  c->add_flag("--wait", s_.wait,
              "wait for the job, print which frames failed, exit as docs/farm.md");
  c->add_option("--poll", s_.poll, "seconds between squeue polls while waiting")
      ->check(CLI::Range(0.1, 3600.0));
  c->add_flag("--dry-run", s_.dry_run, "print the sbatch script and stop");
  c->add_option("--log-dir", s_.log_dir,
                "task logs, result files and the script (default: OUTPUT_FOLDER/isg-farm)");
  c->add_option("--job-name", s_.job_name, "Slurm job name")->capture_default_str();
  c->add_option("--partition", s_.partition, "Slurm partition");
  c->add_option("--sbatch-arg", s_.sbatch_args,
                "another #SBATCH option, e.g. --time=1:00:00 (repeatable)");
  c->add_option("--isg", s_.isg, "the isg executable the tasks run (default: this one)");
  c->add_option("--scene", s_.scene, "scene file (isg run --scene)");
  c->add_option("--preset", s_.preset, "preset name or TOML file (isg run --preset)");
  c->add_option("--set", s_.sets, "section.key=value (isg run --set; repeatable)");
  c->add_option("--channel", s_.channels, "ROLE=NAME (isg run --channel; repeatable)");
  c->add_option("--layer", s_.layer, "Blender view layer (isg run --layer)");
  c->add_option("--compression", s_.compression, "EXR compression (isg run --compression)");
  c->add_option("--device", s_.device, "device index or name on the nodes (isg run --device)");
  c->add_option("--input-colorspace", s_.input_colorspace, "isg run --input-colorspace");
  c->add_flag("--require-gpu", s_.require_gpu, "isg run --require-gpu");

  status_ =
      farm_->add_subcommand("status", "the summary of the last job submitted with a log folder");
  status_->add_option("log_dir", status_dir_, "the job's --log-dir")->required();
  status_->add_flag("--json", status_json_, "machine-readable");
}

int FarmCommand::run() const {
  try {
    if (*submit_) return submit();
    return status();
  } catch (const farm::UsageError& e) {
    std::cerr << "isg: error: " << e.what() << "\n";
    return farm::kUsage;
  }
}

namespace {

fs::path self_exe() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw farm::FarmError("cannot find this executable (/proc/self/exe): " + ec.message());
  return exe;
}

std::string strip_prefix(std::string s) {
  while (!s.empty() && s.back() == '\n') s.pop_back();
  s = s.substr(s.rfind('\n') == std::string::npos ? 0 : s.rfind('\n') + 1);
  const std::string p = "isg: error: ";
  return s.rfind(p, 0) == 0 ? s.substr(p.size()) : s;
}

}  // namespace

int FarmCommand::submit() const {
  const auto& a = s_;
  farm::JobSpec job;
  try {
    job.frames = frames::parse_frames(a.frames);
  } catch (const std::invalid_argument& e) {
    throw farm::UsageError(e.what());
  }
  if (a.chunk < 1)
    throw farm::UsageError("--chunk " + std::to_string(a.chunk) + ": must be at least 1");
  if (a.max_parallel < 0) {
    throw farm::UsageError("--max-parallel " + std::to_string(a.max_parallel) +
                           ": must be 0 (no limit) or more");
  }
  std::sort(job.frames.begin(), job.frames.end());
  job.frames.erase(std::unique(job.frames.begin(), job.frames.end()), job.frames.end());
  for (const auto* p : {&a.input, &a.output}) {
    if (!frames::is_sequence_pattern(*p))
      throw farm::UsageError(*p + ": needs a frame pattern (#### or %04d)");
  }
  // Tasks run elsewhere: every path absolute.
  job.input = fs::absolute(a.input).lexically_normal().string();
  job.output = fs::absolute(a.output).lexically_normal().string();
  const fs::path out_dir = fs::path(job.output).parent_path();
  if (!fs::is_directory(out_dir))
    throw io::IoError(out_dir.string() + ": output folder does not exist");
  job.log_dir = fs::absolute(a.log_dir.empty() ? out_dir / "isg-farm" : fs::path(a.log_dir))
                    .lexically_normal();
  job.workdir = fs::current_path();
  job.chunk = a.chunk;
  job.max_parallel = a.max_parallel;
  job.skip_existing = a.skip_existing;
  job.job_name = a.job_name;
  job.partition = a.partition;
  job.sbatch_args = a.sbatch_args;
  job.isg = a.isg.empty() ? self_exe().string() : fs::absolute(a.isg).string();

  // The options for `isg run`; the parameters are checked here, by the same executable's
  // --print-preset, so a typo fails now (exit 2) rather than in every task.
  std::vector<std::string> params;
  if (!a.preset.empty()) {
    params.insert(params.end(),
                  {"--preset", fs::exists(a.preset) ? fs::absolute(a.preset).string() : a.preset});
  }
  for (const auto& s : a.sets) params.insert(params.end(), {"--set", s});
  if (!a.compression.empty()) params.insert(params.end(), {"--compression", a.compression});
  std::vector<std::string> check{self_exe().string(), "run", "--print-preset"};
  check.insert(check.end(), params.begin(), params.end());
  if (const auto r = farm::run_command(check); r.rc != 0)
    throw farm::UsageError(strip_prefix(r.out));
  job.run_args = params;
  if (!a.scene.empty()) {
    io::read_scene(a.scene);  // IoError naming the file and key
    job.run_args.insert(job.run_args.end(), {"--scene", fs::absolute(a.scene).string()});
  }
  for (const auto& c : a.channels) job.run_args.insert(job.run_args.end(), {"--channel", c});
  if (!a.layer.empty()) job.run_args.insert(job.run_args.end(), {"--layer", a.layer});
  if (!a.device.empty()) job.run_args.insert(job.run_args.end(), {"--device", a.device});
  if (!a.input_colorspace.empty())
    job.run_args.insert(job.run_args.end(), {"--input-colorspace", a.input_colorspace});
  if (a.require_gpu) job.run_args.push_back("--require-gpu");

  if (a.skip_existing) {
    std::vector<int> todo;
    for (int f : job.frames) {
      std::error_code ec;
      const auto out = frames::expand_pattern(job.output, f);
      if (!(fs::is_regular_file(out, ec) && fs::file_size(out, ec) > 0)) todo.push_back(f);
    }
    if (todo.size() < job.frames.size())
      std::cerr << "isg farm: " << job.frames.size() - todo.size() << " of " << job.frames.size()
                << " outputs exist, skipped\n";
    if (todo.empty()) {
      std::cout << "nothing to do: all " << job.frames.size() << " outputs exist\n";
      return farm::kOk;
    }
    job.frames = std::move(todo);
  }
  const auto chunks = farm::make_chunks(job.frames, job.chunk);
  const std::string script = farm::sbatch_script(job, chunks);
  if (a.dry_run) {
    std::cout << script;
    return farm::kOk;
  }
  if (const int limit = farm::max_array_size(); int(chunks.size()) > limit) {
    throw farm::UsageError(std::to_string(chunks.size()) + " tasks exceed Slurm's MaxArraySize (" +
                           std::to_string(limit) + "): raise --chunk");
  }
  std::error_code ec;
  fs::create_directories(job.log_dir, ec);
  if (ec)
    throw farm::FarmError(job.log_dir.string() + ": cannot create the log folder: " + ec.message());
  {
    std::ofstream f(farm::script_file(job.log_dir));
    f << script;
    if (!f) throw farm::FarmError(farm::script_file(job.log_dir).string() + ": cannot write");
  }
  const std::string id = farm::submit(farm::script_file(job.log_dir));
  farm::write_manifest(job.log_dir, {id, job.input, job.output, chunks});
  std::cout << "submitted job " << id << ": " << job.frames.size() << " frame"
            << (job.frames.size() == 1 ? "" : "s") << " in " << chunks.size() << " task"
            << (chunks.size() == 1 ? "" : "s") << " of up to " << job.chunk << " frames; logs in "
            << job.log_dir.string() << "\n";
  if (!a.wait) {
    std::cout << "summary when it is done: isg farm status " << job.log_dir.string() << "\n";
    return farm::kOk;
  }
  farm::wait_for(id, job.log_dir, int(chunks.size()), a.poll, [&](int done) {
    std::cerr << "isg farm: job " << id << ": " << done << "/" << chunks.size()
              << " tasks finished\n";
  });
  const auto summary = farm::summarize(job.log_dir);
  std::cout << farm::describe(summary);
  if (!summary.failed.empty())
    std::cout << "retry after fixing them: the same command with --skip-existing\n";
  return summary.exit_code();
}

int FarmCommand::status() const {
  const auto summary = farm::summarize(status_dir_);
  const auto q = farm::run_command(
      {"squeue", "--noheader", "--array", "--jobs", summary.job_id, "--format", "%i"});
  const bool active = q.rc == 0 && q.out.find_first_not_of(" \n") != std::string::npos;
  if (status_json_) {
    std::cout << farm::to_json(summary);
  } else {
    if (active) std::cout << "job " << summary.job_id << " is still queued or running\n";
    std::cout << farm::describe(summary);
  }
  return active ? farm::kError : summary.exit_code();
}

}  // namespace isg::cli
