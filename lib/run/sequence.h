// Frame sequences (`isg run` with a frame pattern): one device and one Runner for every frame;
// frame i+1 is read (load stage) and frame i−1 written while frame i is on the device. The
// caller prints: what happens is reported through a SequenceObserver.
#pragma once

#include <string>
#include <vector>

#include "run/job.h"
#include "run/run.h"

namespace isg::run {

struct SequenceOptions {
  std::string input, output;  // patterns (#### or %04d)
  std::vector<int> frames;
  bool skip_existing = false;  // leave frames whose output exists (resume)
  bool keep_going = false;     // report a bad frame and go on
};

// Checks the patterns and parses --frames; throws IoError naming what is wrong.
SequenceOptions sequence_options(const std::string& input, const std::string& output,
                                 const std::string& frames, bool skip_existing, bool keep_going);

class SequenceObserver {
 public:
  virtual ~SequenceObserver() = default;
  virtual void skipped(const std::string& what) = 0;   // an output exists (--skip-existing)
  virtual void written(const std::string& what) = 0;   // a frame is done (called from the writer)
  virtual void failed(const std::string& message) = 0;
  virtual void warning(const std::string& message) = 0;
};

// The frames whose output is still to be written (the others reported skipped).
std::vector<int> frames_to_do(const SequenceOptions& o, SequenceObserver& obs);

struct SequenceResult {
  size_t written = 0, failed = 0;
  double gpu_ms = 0;
};

// Runs `todo` on `runner`'s device; stops at the first failure unless keep_going.
SequenceResult run_sequence(Runner& runner, const JobConfig& job, const SequenceOptions& o,
                            const std::vector<int>& todo, SequenceObserver& obs);

// One line per channel of the frame that had NaN/Inf values (set to 0 when it was read).
std::vector<std::string> nonfinite_warnings(const LoadedFrame& f);

}  // namespace isg::run
