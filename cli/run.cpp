// `isg run`: one frame or a sequence, and what --timings prints.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>

#include "cli.h"
#include "effects/dof/focus_view.h"
#include "effects/effect.h"
#include "effects/output_params.h"
#include "gpu/gpu.h"
#include "io/color.h"
#include "roofline/roofline.h"
#include "frames/frames.h"
#include "run/install.h"
#include "run/job.h"
#include "run/options.h"
#include "run/run.h"
#include "run/sequence.h"

namespace isg::cli {

namespace fs = std::filesystem;

namespace {


isg::run::JobOptions run_options(const RunArgs& a) {
  auto o = job_options(a.common, a.compression);
  o.input_colorspace = a.input_colorspace;
  o.no_clobber = a.no_clobber;
  return o;
}

isg::gpu::ContextOptions context_options(const RunArgs& a) {
  isg::gpu::ContextOptions copt;
  copt.device = a.device;
  copt.require_gpu = a.require_gpu;
  copt.validation = a.validation;
  copt.pipeline_cache = isg::gpu::default_pipeline_cache();
  copt.on_message = [](const std::string& m) { std::cerr << "isg: vulkan: " << m << "\n"; };
  return copt;
}

void warn_nonfinite(const isg::run::LoadedFrame& f) {
  for (const auto& w : isg::run::nonfinite_warnings(f)) std::cerr << "isg: warning: " << w << "\n";
}

void print_timings(isg::gpu::Context& ctx, const isg::run::LoadedFrame& f,
                   const isg::run::Stats& st, double init_ms, double write_ms, double total_ms) {
  std::cout << std::fixed << std::setprecision(3);
  std::cout << "device: " << ctx.info().name << " (" << ctx.info().type_name << ")\n";
  std::cout << "GPU time per pass (timestamp queries):\n";
  for (const auto& t : st.passes)
    std::cout << "  " << std::left << std::setw(std::max(28, int(t.name.size()) + 1)) << t.name << t.ms << " ms\n";
  std::cout << "  " << std::setw(28) << "total" << st.gpu_ms() << " ms\n";
  std::cout << "wall: read " << f.read_ms << " ms, ";
  if (f.refit_radius > 0) std::cout << "positions refitted " << f.refit_ms << " ms, ";
  std::cout << "device init (during the read) " << init_ms << " ms, upload "
            << st.upload_ms << " ms, record " << st.record_ms << " ms, submit+wait "
            << st.gpu_wall_ms << " ms, download " << st.download_ms << " ms, write " << write_ms
            << " ms, total " << total_ms << " ms\n";
  std::cout << "GPU memory for the plan: " << f.plan.gpu_bytes() / 1024 << " KiB";
  if (st.tiles > 0)
    std::cout << " (one piece; processed in " << st.tiles << " tiles: "
              << f.img.attributes.get_string("isg:tiles") << ")";
  std::cout << "\n";
  const auto& mem = ctx.memory_use();
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  std::cout << "memory peak: GPU " << double(mem.device_peak) / 1048576.0
            << " MiB device-local + " << double(mem.staging_peak) / 1048576.0
            << " MiB staging (all allocations, measured); host " << double(ru.ru_maxrss) / 1024.0
            << " MiB resident\n";
  for (const auto& r : st.reports)
    for (const auto& line : isg::effects::effect_named(r.effect).describe(r)) std::cout << line << "\n";
  // The gather passes against the roofline (a plain cross-bilateral gather, `isg roofline`),
  // measured now on the same device at the frame's size.
  double roof = 0;
  if (!st.gathers.empty())
    roof = isg::roofline::roofline_taps_per_second(ctx, std::max(f.img.width, 64), std::max(f.img.height, 64));
  for (const auto& g : st.gathers) {
    double ms = 0;
    for (const auto& t : st.passes)
      ms += t.name == g.pass || std::ranges::find(g.dispatches, t.name) != g.dispatches.end() ? t.ms : 0.0;
    const double rate = ms > 0 ? double(g.samples) / (ms * 1e-3) : 0.0;
    const double taps = rate * g.taps_per_sample;
    std::cout << g.pass << ": " << g.pixels << " pixels, " << g.samples << " samples ("
              << (g.pixels ? double(g.samples) / double(g.pixels) : 0.0) << " a pixel; "
              << g.taps_per_sample << (g.taps_per_sample == 1 ? " tap" : " taps") << " a sample), "
              << rate * 1e-6 << " M samples/s, " << taps * 1e-6 << " M taps/s = "
              << (roof > 0 ? 100.0 * taps / roof : 0.0) << "% of the roofline (" << roof * 1e-6
              << " M taps/s, isg roofline)\n";
  }
}

int run_single(const RunArgs& a, isg::run::JobConfig& job) {
  auto t_start = Clock::now();
  if (a.dry_run) {
    auto f = isg::run::plan_frame(job, a.input);
    std::cout << f.plan.describe();
    return f.plan.missing.empty() ? kOk : kError;
  }
  isg::io::check_writable(a.output, job.write);
  if (!a.preview.empty()) isg::io::check_writable(a.preview, job.write);
  if (!a.focus_view.empty()) isg::io::check_writable(a.focus_view, job.write);
  // The device starts while the frame is read (issue 18): lavapipe's start-up is LLVM and the
  // pipeline cache, the read mostly waits on the decoder child, so the two overlap.
  std::optional<isg::gpu::Context> gpu;
  std::exception_ptr gpu_error;
  double init_ms = 0;
  std::jthread starter([&] {
    auto t = Clock::now();
    try {
      gpu.emplace(context_options(a));
    } catch (...) {
      gpu_error = std::current_exception();
    }
    init_ms = ms_since(t);
  });
  auto f = isg::run::load_frame(job, a.input);
  warn_nonfinite(f);
  if (!a.focus_view.empty()) {  // before any work: the view pictures depth of field's CoC
    for (const auto& e : f.plan.effects)
      if (e.effect == "dof" && !e.runs)
        throw isg::io::IoError(a.focus_view + ": --focus-view needs depth of field, which does not run (" + e.why + ")");
  }
  starter.join();
  if (gpu_error) std::rethrow_exception(gpu_error);
  isg::gpu::Context& ctx = *gpu;
  auto st = isg::run::process_frame(ctx, job, f);
  for (const auto& w : st.warnings) std::cerr << "isg: warning: " << w << "\n";
  // What the effects chose from the pixels (shadows.method = auto), and why; notes on a method
  // named where another suits the frame better.
  for (const auto& e : f.plan.effects)
    if (e.why.rfind("auto: ", 0) == 0 || e.why.rfind("note: ", 0) == 0)
      std::cout << e.effect << ": " << e.method << " (" << e.why << ")\n";
  double write_ms = isg::run::write_frame(job, f, a.output);
  std::cout << "wrote " << a.output << " (" << f.img.width << "x" << f.img.height << ", "
            << f.img.channels.size() << " channels)\n";
  if (!a.preview.empty()) {
    auto pic = isg::io::display_picture(f.img, {"R", "G", "B"}, {});
    isg::io::write_picture(a.preview, f.img.width, f.img.height, pic, a.no_clobber);
    std::cout << "wrote " << a.preview << " (display picture, OpenColorIO "
              << isg::io::color_config_description() << ")\n";
  }
  if (!a.focus_view.empty()) {
    const auto* coc = f.img.find("dof.coc");
    if (!coc) throw isg::io::IoError(a.focus_view + ": --focus-view: no dof.coc (depth of field did not run)");
    auto pic = isg::effects::focus_picture(isg::io::display_picture(f.img, {"R", "G", "B"}, {}), coc->data);
    isg::io::write_picture(a.focus_view, f.img.width, f.img.height, pic, a.no_clobber);
    std::cout << "wrote " << a.focus_view << " (focus view: in focus green, nearer blue, farther orange)\n";
  }
  if (a.timings) print_timings(ctx, f, st, init_ms, write_ms, ms_since(t_start));
  return kOk;
}

// Progress on a terminal (one line, redrawn) or plain lines for logs.
class Progress {
 public:
  explicit Progress(size_t total) : total_(total), tty_(::isatty(2)), start_(Clock::now()) {}
  void frame(const std::string& what, bool done_one) {
    if (done_one) ++done_;
    double s = ms_since(start_) / 1000.0;
    double rate = s > 0 ? double(done_) / s : 0;
    double eta = rate > 0 ? double(total_ - done_ - skipped_ - failed_) / rate : 0;
    std::ostringstream line;
    line << std::fixed << std::setprecision(2) << done_ + skipped_ + failed_ << "/" << total_
         << " frames, " << rate << " fps, ETA " << std::setprecision(0) << eta << " s";
    if (tty_) {
      size_t n = done_ + skipped_ + failed_;
      int width = 30, filled = total_ ? int(width * n / total_) : width;
      std::cerr << "\r[" << std::string(filled, '=') << std::string(width - filled, ' ') << "] "
                << line.str() << "  " << what << "\x1b[K" << std::flush;
    } else {
      std::cerr << what << " (" << line.str() << ")\n";
    }
  }
  void skipped(const std::string& what) {
    ++skipped_;
    frame(what, false);
  }
  void failed(const std::string& msg) {
    ++failed_;
    if (tty_) std::cerr << "\r\x1b[K";
    std::cerr << "isg: error: " << msg << "\n";
  }
  void finish() const {
    if (tty_) std::cerr << "\n";
  }
  size_t done() const { return done_; }
  size_t failed_count() const { return failed_; }
  size_t skipped_count() const { return skipped_; }
  double seconds() const { return ms_since(start_) / 1000.0; }

 private:
  size_t total_, done_ = 0, skipped_ = 0, failed_ = 0;
  bool tty_;
  Clock::time_point start_;
};

// A frame range (lib/run/sequence.h schedules it; here it is printed).
class ProgressObserver final : public isg::run::SequenceObserver {
 public:
  explicit ProgressObserver(Progress& p) : p_(p) {}
  void skipped(const std::string& what) override { p_.skipped(what); }
  void written(const std::string& what) override { p_.frame(what, true); }
  void failed(const std::string& message) override { p_.failed(message); }
  void warning(const std::string& message) override { std::cerr << "isg: warning: " << message << "\n"; }

 private:
  Progress& p_;
};

int run_sequence(const RunArgs& a, isg::run::JobConfig& job) {
  const auto seq = isg::run::sequence_options(a.input, a.output, a.frames, a.skip_existing, a.keep_going);
  if (a.dry_run) {
    auto f = isg::run::plan_frame(job, isg::frames::expand_pattern(a.input, seq.frames.front()));
    std::cout << seq.frames.size() << " frames; first frame's " << f.plan.describe();
    return f.plan.missing.empty() ? kOk : kError;
  }
  isg::io::check_writable(isg::frames::expand_pattern(a.output, seq.frames.front()), {job.write.compression, false});
  Progress progress(seq.frames.size());
  ProgressObserver obs(progress);
  const auto todo = isg::run::frames_to_do(seq, obs);
  if (todo.empty()) {
    progress.finish();
    std::cout << "nothing to do: all " << seq.frames.size() << " outputs exist\n";
    return kOk;
  }
  isg::gpu::Context ctx(context_options(a));
  isg::run::Runner runner(ctx);
  const auto res = isg::run::run_sequence(runner, job, seq, todo, obs);
  progress.finish();
  std::cout << std::fixed << std::setprecision(2) << "frames: " << progress.done() << " written, "
            << progress.skipped_count() << " skipped (existing), " << progress.failed_count()
            << " failed, in " << progress.seconds() << " s ("
            << (progress.seconds() > 0 ? double(progress.done()) / progress.seconds() : 0.0)
            << " fps; GPU " << res.gpu_ms << " ms)\n";
  if (progress.failed_count() == 0) return kOk;
  return a.keep_going ? kSomeFramesFailed : kError;
}

}  // namespace

int cmd_run(const RunArgs& a) {
  const auto o = run_options(a);
  const auto layout = isg::run::executable_layout();
  if (a.print_preset) {
    std::cout << isg::run::job_params(o, layout).to_toml();
    return kOk;
  }
  if (a.input.empty()) throw isg::io::IoError("isg run: no input file given");
  if (a.output.empty() && !a.dry_run) throw isg::io::IoError("isg run: no output given (-o FILE)");
  auto job = isg::run::make_job(o, layout, ISG_VERSION);
  if (isg::frames::is_sequence_pattern(a.input) && !fs::exists(a.input)) {
    if (!a.focus_view.empty()) throw isg::io::IoError(a.focus_view + ": --focus-view takes one frame, not a sequence");
    return run_sequence(a, job);
  }
  if (!a.frames.empty()) throw isg::io::IoError(a.input + ": --frames needs a frame pattern (#### or %04d) in the input");
  if (!a.dry_run) {
    std::error_code ec;
    if (fs::exists(a.output, ec) && fs::equivalent(a.input, a.output, ec)) {
      throw isg::io::IoError(a.output + ": is the input file; isg never overwrites its input");
    }
  }
  return run_single(a, job);
}


}  // namespace isg::cli
