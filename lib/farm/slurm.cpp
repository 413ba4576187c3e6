// Slurm's client commands (sbatch, squeue, scontrol, scancel), run as child processes: no
// library to link, and the same commands a user would type.
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <regex>
#include <thread>

#include "farm/farm.h"

namespace isg::farm {

namespace fs = std::filesystem;

CommandResult run_command(const std::vector<std::string>& argv) {
  int fds[2];
  if (argv.empty() || ::pipe(fds) != 0)
    throw FarmError("cannot start a command: " + std::string(std::strerror(errno)));
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw FarmError(argv[0] + ": cannot fork: " + std::strerror(errno));
  }
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    ::close(fds[1]);
    ::execvp(args[0], args.data());
    const std::string msg = argv[0] + ": cannot run: " + std::strerror(errno) + "\n";
    if (::write(2, msg.data(), msg.size()) < 0) {
    }
    ::_exit(127);
  }
  ::close(fds[1]);
  CommandResult r;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      r.out.append(buf, size_t(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

namespace {
std::string last_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  const auto nl = s.rfind('\n');
  return nl == std::string::npos ? s : s.substr(nl + 1);
}
}  // namespace

int max_array_size() {
  const auto r = run_command({"scontrol", "show", "config"});
  std::smatch m;
  static const std::regex re(R"(MaxArraySize\s*=\s*(\d+))");
  if (r.rc == 0 && std::regex_search(r.out, m, re)) return std::stoi(m[1].str());
  return 1001;
}

std::string submit(const fs::path& script) {
  const auto r = run_command({"sbatch", "--parsable", script.string()});
  if (r.rc != 0) {
    throw FarmError("sbatch " + script.string() + ": " +
                    (r.out.empty() ? "exit " + std::to_string(r.rc) : last_line(r.out)));
  }
  // --parsable prints "jobid" or "jobid;cluster" (after any warnings).
  std::string id = last_line(r.out);
  id = id.substr(0, id.find(';'));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    throw FarmError("sbatch " + script.string() + ": no job id in its answer: " + last_line(r.out));
  }
  return id;
}

void wait_for(const std::string& job_id, const fs::path& log_dir, int tasks, double poll_s,
              const std::function<void(int)>& progress) {
  using Clock = std::chrono::steady_clock;
  auto finished = [&] {
    int n = 0;
    for (int t = 0; t < tasks; ++t) n += fs::exists(task_result(log_dir, job_id, t)) ? 1 : 0;
    return n;
  };
  int reported = -1;
  auto failing_since = Clock::now();
  bool failing = false;
  for (;;) {
    const int n = finished();
    if (n != reported) {
      progress(n);
      reported = n;
    }
    // Queued, running or completing tasks of the job, one line each; nothing once all are done.
    const auto r =
        run_command({"squeue", "--noheader", "--array", "--jobs", job_id, "--format", "%i %T"});
    if (r.rc == 0) {
      failing = false;
      if (r.out.find_first_not_of(" \n") == std::string::npos) break;
    } else if (r.out.find("Invalid job id") != std::string::npos) {
      break;  // already purged from slurmctld's memory (MinJobAge): done
    } else {
      if (!failing) failing_since = Clock::now();
      failing = true;
      if (Clock::now() - failing_since > std::chrono::seconds(60)) {
        throw FarmError("squeue --jobs " + job_id + ": " + last_line(r.out));
      }
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_s));
  }
  // A task writes its result file before it ends; on a shared file system the file may show up
  // here a little later than squeue lets go of the task.
  const auto until = Clock::now() + std::chrono::seconds(10);
  while (finished() < tasks && Clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  if (finished() != reported) progress(finished());
}

void cancel(const std::string& job_id) { run_command({"scancel", job_id}); }

}  // namespace isg::farm
