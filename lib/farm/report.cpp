// The summary of a farm job, read back from what its tasks left: one result file each (exit
// status and frames), their logs (`isg run`'s error and count lines) and the outputs on disk.
// Outputs are written atomically, so an output that exists is complete; a frame without one
// failed, whatever the logs say.
#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "farm/farm.h"
#include "frames/frames.h"

namespace isg::farm {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

struct LogFacts {
  bool counted = false;
  size_t written = 0, skipped = 0;
  std::map<int, std::string> frame_errors;
  std::vector<std::string> errors;
};

// `isg run` on a sequence writes "isg: error: frame N: ..." per bad frame, "isg: error: ..." for
// a run that stops, and "frames: W written, S skipped (existing), F failed" at the end.
LogFacts read_log(const fs::path& log) {
  static const std::regex frame_error(R"(^isg: error: frame (-?\d+): (.*)$)");
  static const std::regex error(R"(^isg: error: (.*)$)");
  static const std::regex counts(
      R"(^frames: (\d+) written, (\d+) skipped \(existing\), (\d+) failed)");
  static const std::regex nothing(R"(^nothing to do: all (\d+) outputs exist)");
  LogFacts f;
  std::ifstream in(log);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    // A progress bar redrawn with \r leaves its last state after the last \r.
    const auto cr = line.rfind('\r');
    if (cr != std::string::npos) line = line.substr(cr + 1);
    if (std::regex_search(line, m, frame_error)) {
      f.frame_errors[std::stoi(m[1].str())] = m[2].str();
    } else if (std::regex_search(line, m, error)) {
      f.errors.push_back(m[1].str());
    } else if (std::regex_search(line, m, counts)) {
      f.counted = true;
      f.written += std::stoul(m[1].str());
      f.skipped += std::stoul(m[2].str());
    } else if (std::regex_search(line, m, nothing)) {
      f.counted = true;
      f.skipped += std::stoul(m[1].str());
    }
  }
  return f;
}

bool output_exists(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && fs::file_size(path, ec) > 0;
}

}  // namespace

Summary summarize(const fs::path& log_dir) {
  const Manifest m = read_manifest(log_dir);
  Summary s;
  s.job_id = m.job_id;
  s.output = m.output;
  for (const auto& c : m.chunks) {
    TaskReport t;
    t.task = c.task;
    t.spec = c.spec;
    t.log = task_log(log_dir, m.job_id, c.task);
    const fs::path result = task_result(log_dir, m.job_id, c.task);
    if (std::ifstream r(result); r) {
      int rc = 0;
      if (!(r >> rc))
        throw FarmError(result.string() + ": not a result line (exit status, frames)");
      t.exit = rc;
    }
    const LogFacts log = read_log(t.log);
    t.errors = log.errors;
    size_t present = 0;
    for (int f : c.frames) {
      if (output_exists(frames::expand_pattern(m.output, f))) {
        ++present;
        continue;
      }
      std::string why;
      if (auto e = log.frame_errors.find(f); e != log.frame_errors.end()) {
        why = e->second;
      } else if (!log.errors.empty()) {
        why = log.errors.front();
      } else if (!t.exit) {
        why = "task " + std::to_string(c.task) +
              " left no result (not run, cancelled or killed); see " + t.log.string();
      } else {
        why = "no output written; see " + t.log.string();
      }
      s.failed.push_back({f, c.task, why});
    }
    s.frames += c.frames.size();
    if (log.counted) {
      s.written += log.written;
      s.skipped += log.skipped;
    } else {
      s.written += present;
    }
    s.tasks.push_back(std::move(t));
  }
  std::sort(s.failed.begin(), s.failed.end(),
            [](const FrameFailure& a, const FrameFailure& b) { return a.frame < b.frame; });
  return s;
}

int Summary::exit_code() const {
  bool usage = false, error = false;
  for (const auto& t : tasks) {
    if (t.exit && *t.exit == kUsage) {
      usage = true;
    } else if (!t.exit || (*t.exit != kOk && *t.exit != kSomeFramesFailed)) {
      error = true;
    }
  }
  if (usage) return kUsage;
  if (error) return kError;
  return failed.empty() ? kOk : kSomeFramesFailed;
}

std::string describe(const Summary& s) {
  std::ostringstream o;
  o << "job " << s.job_id << ": " << s.frames << " frame" << (s.frames == 1 ? "" : "s") << " in "
    << s.tasks.size() << " task" << (s.tasks.size() == 1 ? "" : "s") << ": " << s.written
    << " written, " << s.skipped << " skipped (existing), " << s.failed.size() << " failed\n";
  if (!s.failed.empty()) {
    // A short list as it is (what a person reads); a long one in --frames syntax.
    std::vector<int> frames;
    std::string list;
    for (const auto& f : s.failed) {
      frames.push_back(f.frame);
      list += (list.empty() ? "" : ",") + std::to_string(f.frame);
    }
    o << "failed frames: " << (frames.size() <= 20 ? list : frames_spec(frames)) << "\n";
    for (const auto& f : s.failed)
      o << "  frame " << f.frame << " (task " << f.task << "): " << f.message << "\n";
  }
  for (const auto& t : s.tasks) {
    if (t.exit && (*t.exit == kOk || *t.exit == kSomeFramesFailed)) continue;
    o << "task " << t.task << " (frames " << t.spec
      << "): " << (t.exit ? "exit " + std::to_string(*t.exit) : std::string("no result"))
      << ", log " << t.log.string() << "\n";
  }
  return o.str();
}

std::string to_json(const Summary& s) {
  json j{{"job_id", s.job_id},      {"output", s.output},    {"frames", s.frames},
         {"written", s.written},    {"skipped", s.skipped},  {"exit", s.exit_code()},
         {"failed", json::array()}, {"tasks", json::array()}};
  for (const auto& f : s.failed)
    j["failed"].push_back({{"frame", f.frame}, {"task", f.task}, {"message", f.message}});
  for (const auto& t : s.tasks) {
    j["tasks"].push_back({{"task", t.task},
                          {"frames", t.spec},
                          {"exit", t.exit ? json(*t.exit) : json(nullptr)},
                          {"log", t.log.string()},
                          {"errors", t.errors}});
  }
  return j.dump(2) + "\n";
}

}  // namespace isg::farm
