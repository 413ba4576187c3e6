// Chunks, the sbatch script and the files of a log folder.
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "farm/farm.h"

namespace isg::farm {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string frames_spec(const std::vector<int>& frames) {
  std::string s;
  size_t i = 0;
  while (i < frames.size()) {
    size_t j = i;
    const long long step = i + 1 < frames.size() ? (long long)frames[i + 1] - frames[i] : 0;
    while (step > 0 && j + 1 < frames.size() && (long long)frames[j + 1] - frames[j] == step) ++j;
    const size_t n = j - i + 1;
    if (!s.empty()) s += ',';
    if (step == 1 && n >= 2) {
      s += std::to_string(frames[i]) + "-" + std::to_string(frames[j]);
    } else if (step > 1 && n >= 3) {
      s += std::to_string(frames[i]) + "-" + std::to_string(frames[j]) + "x" + std::to_string(step);
    } else {
      s += std::to_string(frames[i]);
      j = i;
    }
    i = j + 1;
  }
  return s;
}

std::vector<Chunk> make_chunks(const std::vector<int>& frames, int size) {
  if (size < 1) throw UsageError("--chunk " + std::to_string(size) + ": must be at least 1");
  std::vector<Chunk> chunks;
  for (size_t i = 0; i < frames.size(); i += size_t(size)) {
    Chunk c;
    c.task = int(chunks.size());
    c.frames.assign(frames.begin() + ptrdiff_t(i),
                    frames.begin() + ptrdiff_t(std::min(frames.size(), i + size_t(size))));
    c.spec = frames_spec(c.frames);
    chunks.push_back(std::move(c));
  }
  return chunks;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void check_sbatch_path(const fs::path& p, const std::string& what) {
  const std::string s = p.string();
  if (s.find_first_of(" \t\n\"'%\\") != std::string::npos) {
    throw UsageError(what + " " + s +
                     ": an #SBATCH line cannot hold spaces, quotes, backslashes or '%'; "
                     "choose another folder");
  }
}

std::string sbatch_script(const JobSpec& job, const std::vector<Chunk>& chunks) {
  if (chunks.empty()) throw UsageError("isg farm: no frames to submit");
  check_sbatch_path(job.log_dir, "--log-dir");
  check_sbatch_path(job.workdir, "working folder");
  const int tasks = int(chunks.size());
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# isg farm submit: " << job.frames.size() << " frames of " << job.input << " in " << tasks
    << " task" << (tasks == 1 ? "" : "s") << " of up to " << job.chunk << " frames.\n"
    << "# The array index picks a row of the frame table below, so indices stay 0-" << tasks - 1
    << "\n# (under Slurm's MaxArraySize) whatever the frame numbers are.\n";
  s << "#SBATCH --job-name=" << job.job_name << "\n"
    << "#SBATCH --array=0-" << tasks - 1;
  if (job.max_parallel > 0) s << "%" << job.max_parallel;
  s << "\n#SBATCH --output=" << job.log_dir.string() << "/%A.%a.log\n"
    << "#SBATCH --chdir=" << job.workdir.string() << "\n";
  if (!job.partition.empty()) s << "#SBATCH --partition=" << job.partition << "\n";
  for (const auto& a : job.sbatch_args) s << "#SBATCH " << a << "\n";
  s << "\nframes=(\n";
  for (const auto& c : chunks) s << "  " << c.spec << "\n";
  s << ")\n"
    << "task=${SLURM_ARRAY_TASK_ID:?submit this script with sbatch: it is an array job}\n"
    << "job=${SLURM_ARRAY_JOB_ID:-$SLURM_JOB_ID}\n"
    << "spec=${frames[$task]}\n"
    << "echo \"isg farm: job $job task $task on $(hostname): frames $spec\"\n";
  s << shell_quote(job.isg) << " run " << shell_quote(job.input) << " -o "
    << shell_quote(job.output) << " --frames \"$spec\" --keep-going";
  if (job.skip_existing) s << " --skip-existing";
  for (const auto& a : job.run_args) s << " " << shell_quote(a);
  s << "\nrc=$?\n"
    << "# One line for `isg farm status`: the exit status (docs/farm.md) and the frames; written\n"
    << "# whole (rename) so a reader never sees half of it.\n"
    << "result=" << shell_quote(job.log_dir.string()) << "/$job.$task.result\n"
    << "echo \"$rc $spec\" > \"$result.tmp\" && mv -f \"$result.tmp\" \"$result\"\n"
    << "exit $rc\n";
  return s.str();
}

fs::path script_file(const fs::path& log_dir) { return log_dir / "isg-farm.sbatch"; }
fs::path manifest_file(const fs::path& log_dir) { return log_dir / "isg-farm.json"; }
fs::path task_log(const fs::path& log_dir, const std::string& job, int task) {
  return log_dir / (job + "." + std::to_string(task) + ".log");
}
fs::path task_result(const fs::path& log_dir, const std::string& job, int task) {
  return log_dir / (job + "." + std::to_string(task) + ".result");
}

void write_manifest(const fs::path& log_dir, const Manifest& m) {
  json j{{"job_id", m.job_id}, {"input", m.input}, {"output", m.output}, {"chunks", json::array()}};
  for (const auto& c : m.chunks) j["chunks"].push_back({{"task", c.task}, {"frames", c.frames}});
  const fs::path path = manifest_file(log_dir), tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp);
    f << j.dump(1) << "\n";
    if (!f) throw FarmError(tmp.string() + ": cannot write");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw FarmError(path.string() + ": " + ec.message());
}

Manifest read_manifest(const fs::path& log_dir) {
  const fs::path path = manifest_file(log_dir);
  std::ifstream f(path);
  if (!f) throw FarmError(path.string() + ": no such file (not a log folder of isg farm submit)");
  Manifest m;
  try {
    const json j = json::parse(f);
    m.job_id = j.at("job_id").get<std::string>();
    m.input = j.at("input").get<std::string>();
    m.output = j.at("output").get<std::string>();
    for (const auto& c : j.at("chunks")) {
      Chunk ch{c.at("task").get<int>(), c.at("frames").get<std::vector<int>>(), {}};
      ch.spec = frames_spec(ch.frames);
      m.chunks.push_back(std::move(ch));
    }
  } catch (const json::exception& e) {
    throw FarmError(path.string() + ": " + e.what());
  }
  return m;
}

}  // namespace isg::farm
