#include "run/sequence.h"

#include "frames/frames.h"

#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>

namespace isg::run {

namespace fs = std::filesystem;

SequenceOptions sequence_options(const std::string& input, const std::string& output,
                                 const std::string& frames, bool skip_existing, bool keep_going) {
  if (frames.empty()) throw io::IoError(input + ": a frame pattern needs --frames A-B");
  if (!isg::frames::is_sequence_pattern(output)) {
    throw io::IoError(output + ": -o needs a frame pattern (#### or %04d) for a sequence");
  }
  SequenceOptions o{input, output, {}, skip_existing, keep_going};
  try {
    o.frames = isg::frames::parse_frames(frames);
  } catch (const std::invalid_argument& e) {
    throw io::IoError(e.what());
  }
  return o;
}

std::vector<int> frames_to_do(const SequenceOptions& o, SequenceObserver& obs) {
  std::vector<int> todo;
  for (int fr : o.frames) {
    std::string out = isg::frames::expand_pattern(o.output, fr);
    std::error_code ec;
    if (o.skip_existing && fs::exists(out, ec) && fs::file_size(out, ec) > 0) {
      obs.skipped("frame " + std::to_string(fr) + ": " + out + " exists, skipped");
    } else {
      todo.push_back(fr);
    }
  }
  return todo;
}

std::vector<std::string> nonfinite_warnings(const LoadedFrame& f) {
  std::vector<std::string> w;
  for (const auto& nf : f.nonfinite) {
    w.push_back(f.input + ": channel " + nf.channel + " had " + std::to_string(nf.count) +
                " NaN/Inf values, set to 0");
  }
  return w;
}

SequenceResult run_sequence(Runner& runner, const JobConfig& job, const SequenceOptions& o,
                            const std::vector<int>& todo, SequenceObserver& obs) {
  SequenceResult res;
  if (todo.empty()) return res;
  auto load = [&](int fr) {
    return std::async(std::launch::async, [&job, &o, fr] {
      return load_frame(job, isg::frames::expand_pattern(o.input, fr));
    });
  };
  std::future<LoadedFrame> next = load(todo.front());
  std::future<void> writing;
  std::string write_error;
  auto finish_write = [&] {
    if (!writing.valid()) return;
    try {
      writing.get();
    } catch (const std::exception& e) {
      write_error = e.what();
    }
  };
  for (size_t i = 0; i < todo.size(); ++i) {
    const int fr = todo[i];
    const std::string out = isg::frames::expand_pattern(o.output, fr);
    std::optional<LoadedFrame> f;
    std::string error;
    try {
      f.emplace(next.get());
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (i + 1 < todo.size()) next = load(todo[i + 1]);
    if (f) {
      try {
        for (const auto& w : nonfinite_warnings(*f)) obs.warning(w);
        const auto st = process_frame(runner, job, *f);
        for (const auto& w : st.warnings) obs.warning(w);
        res.gpu_ms += st.gpu_ms();
      } catch (const std::exception& e) {
        error = e.what();
        f.reset();
      }
    }
    finish_write();
    if (!write_error.empty()) {
      obs.failed(write_error);
      ++res.failed;
      write_error.clear();
      if (!o.keep_going) break;
    }
    if (!error.empty()) {
      obs.failed("frame " + std::to_string(fr) + ": " + error);
      ++res.failed;
      if (!o.keep_going) break;
      continue;
    }
    auto shared = std::make_shared<LoadedFrame>(std::move(*f));
    writing = std::async(std::launch::async, [&job, &obs, &res, shared, out, fr] {
      write_frame(job, *shared, out);
      ++res.written;
      obs.written("frame " + std::to_string(fr) + ": wrote " + out);
    });
  }
  finish_write();
  if (!write_error.empty()) {
    obs.failed(write_error);
    ++res.failed;
  }
  if (next.valid()) next.wait();
  return res;
}

}  // namespace isg::run
