// Frame ranges on a Slurm farm (`isg farm`). A range is split into chunks, one array task per
// chunk. The task id indexes a table of frame specs written into the job script, so the array
// indices stay 0..tasks-1 (under Slurm's default MaxArraySize of 1001) whatever the frame numbers
// are: 1001-1100 needs no change to slurm.conf. Each task runs `isg run --frames SPEC
// --keep-going`, writes its log and a one-line result file into the log folder; the summary is
// read back from those and from the outputs on disk.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace isg::farm {

// Anything wrong with Slurm, the log folder or a result file; one line naming what it is about.
struct FarmError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A bad command line (exit 2): a frame spec, a chunk size, a path Slurm cannot take.
struct UsageError : FarmError {
  using FarmError::FarmError;
};

// The exit status of `isg run` on a sequence and of `isg farm` (docs/farm.md).
enum Exit { kOk = 0, kError = 1, kUsage = 2, kSomeFramesFailed = 3 };

// One array task: its index and the frames it runs.
struct Chunk {
  int task = 0;
  std::vector<int> frames;
  std::string spec;  // the frames as `isg run --frames` reads them
};

// The shortest spelling of ascending `frames` in `--frames` syntax: runs of equal steps become
// A-B or A-BxS, the rest a comma list (parse_frames(frames_spec(f)) == f).
std::string frames_spec(const std::vector<int>& frames);
// Consecutive chunks of at most `size` frames, tasks numbered from 0.
std::vector<Chunk> make_chunks(const std::vector<int>& frames, int size);

// What to submit. Paths are absolute by the time a script is written (tasks run elsewhere).
struct JobSpec {
  std::string input, output;          // frame patterns (#### or %04d)
  std::vector<int> frames;            // frames to process, ascending
  int chunk = 10;                     // frames per task
  int max_parallel = 0;               // tasks running at once (%N); 0: no limit
  std::string isg;                    // the executable the tasks run
  std::vector<std::string> run_args;  // more `isg run` options (--scene F, --preset P, ...)
  bool skip_existing = false;
  std::string job_name = "isg";
  std::filesystem::path log_dir;  // logs, result files, the script and the manifest
  std::filesystem::path workdir;  // the tasks' working folder (--chdir)
  std::string partition;
  std::vector<std::string> sbatch_args;  // more #SBATCH options, e.g. --time=1:00:00
};

// Single quotes for bash, whatever the text holds.
std::string shell_quote(const std::string& s);
// Throws UsageError when a path cannot go into an #SBATCH line (whitespace, quotes, '%').
void check_sbatch_path(const std::filesystem::path& p, const std::string& what);
// The sbatch script for `chunks` (what `isg farm submit --dry-run` prints).
std::string sbatch_script(const JobSpec& job, const std::vector<Chunk>& chunks);

// Files in the log folder.
std::filesystem::path script_file(const std::filesystem::path& log_dir);    // isg-farm.sbatch
std::filesystem::path manifest_file(const std::filesystem::path& log_dir);  // isg-farm.json
std::filesystem::path task_log(const std::filesystem::path& log_dir, const std::string& job,
                               int task);
std::filesystem::path task_result(const std::filesystem::path& log_dir, const std::string& job,
                                  int task);

// The last job submitted from a log folder: enough to summarise it later.
struct Manifest {
  std::string job_id;
  std::string input, output;
  std::vector<Chunk> chunks;
};
void write_manifest(const std::filesystem::path& log_dir, const Manifest& m);
Manifest read_manifest(const std::filesystem::path& log_dir);  // FarmError naming the file

// ---- Slurm (slurm.cpp) ----

// A command's exit status and its stdout and stderr together. The program is looked up on PATH;
// one that cannot be started gives rc 127 and says why.
struct CommandResult {
  int rc = -1;
  std::string out;
};
CommandResult run_command(const std::vector<std::string>& argv);

// Slurm's MaxArraySize (`scontrol show config`), or 1001 (its default) when it cannot be read.
int max_array_size();
// `sbatch --parsable script`: the job id. FarmError with sbatch's own message on failure.
std::string submit(const std::filesystem::path& script);
// Waits until no task of `job_id` is queued or running (squeue), polling every `poll_s` seconds;
// `progress(tasks finished)` is called whenever that count changes.
void wait_for(const std::string& job_id, const std::filesystem::path& log_dir, int tasks,
              double poll_s, const std::function<void(int)>& progress);
// `scancel job_id` (after an interrupted wait); errors are ignored.
void cancel(const std::string& job_id);

// ---- The summary (report.cpp) ----

struct TaskReport {
  int task = 0;
  std::string spec;
  std::optional<int> exit;  // absent: the task left no result file (never ran, killed, ...)
  std::filesystem::path log;
  std::vector<std::string> errors;  // `isg: error:` lines that name no frame
};
struct FrameFailure {
  int frame = 0;
  int task = 0;
  std::string message;  // from the task's log, else why the frame counts as failed
};
struct Summary {
  std::string job_id;
  std::string output;
  size_t frames = 0, written = 0, skipped = 0;
  std::vector<FrameFailure> failed;  // every frame whose output is absent, ascending
  std::vector<TaskReport> tasks;
  int exit_code() const;  // 0, 1 (a task failed as a whole or left no result), 2, or 3
};
// Reads the manifest, each task's result file and log, and looks for every frame's output.
Summary summarize(const std::filesystem::path& log_dir);
// The summary for people (what `isg farm submit --wait` and `isg farm status` print).
std::string describe(const Summary& s);
std::string to_json(const Summary& s);

}  // namespace isg::farm
