// `import isg`: the job-level entry points of `isg run` (lib/run/job.h) for pipeline scripts.
// Files in, files out, or NumPy arrays in and out, with the CLI's parameters and presets; errors
// are Python exceptions carrying the library's one-line message (file, channel or key).
#include <OpenImageIO/imageio.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <iostream>
#include <memory>

#include "gpu/gpu.h"
#include "io/image.h"
#include "io/roles.h"
#include "params/params.h"
#include "run/install.h"
#include "run/job.h"
#include "run/options.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace isg::python {
namespace {

// A device set up once and passed to any number of calls (no module-level state).
class Context {
 public:
  Context(const std::string& device, bool require_gpu, bool validation) {
    gpu::ContextOptions o;
    o.device = device;
    o.require_gpu = require_gpu;
    o.validation = validation;
    o.pipeline_cache = gpu::default_pipeline_cache();
    o.on_message = [](const std::string& m) { std::cerr << "isg: vulkan: " << m << "\n"; };
    ctx_ = std::make_unique<gpu::Context>(o);
  }
  gpu::Context& get() { return *ctx_; }
  std::string device() const { return ctx_->info().name + " (" + ctx_->info().type_name + ")"; }

 private:
  std::unique_ptr<gpu::Context> ctx_;
};

// Text for --set from a Python value: True -> "true", 0.5 -> "0.5", "vssm" -> "vssm".
std::string value_text(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  return py::str(v).cast<std::string>();
}

// Where the module finds presets and isg-exrcheck: by its own file, as the CLI does by its
// executable (run/install.h). ISG_PYTHON_TO_PREFIX: from its folder to the install prefix
// (python/CMakeLists.txt: .../dist-packages -> ../../..).
run::Layout module_layout() {
  static const int anchor = 0;
  return run::layout_of(run::object_file_of(&anchor), ISG_PYTHON_TO_PREFIX);
}

// The job of `isg run` with these options (run::make_job, the CLI's assembly).
run::JobConfig make_job(const run::JobOptions& o) { return run::make_job(o, module_layout(), ISG_VERSION); }

run::JobOptions options(const py::object& scene, const py::object& preset, const py::object& set,
                const py::object& channels, const py::object& layer, const py::object& compression,
                const py::object& input_colorspace, bool no_clobber) {
  auto text = [](const py::object& o) {
    return o.is_none() ? std::string() : py::str(o).cast<std::string>();
  };
  run::JobOptions o;
  o.set_label = "set";  // errors name Python's keywords
  o.channel_label = "channels";
  o.compression_label = "compression";
  o.scene = text(scene);  // str or os.PathLike
  o.preset = text(preset);
  o.layer = text(layer);
  o.compression = text(compression);
  o.input_colorspace = text(input_colorspace);
  o.no_clobber = no_clobber;
  // set: {"shadows.method": "hard"} or ["shadows.method=hard", ...]
  if (py::isinstance<py::dict>(set)) {
    for (auto [k, v] : set.cast<py::dict>())
      o.sets.push_back(py::str(k).cast<std::string>() + "=" + value_text(v));
  } else if (!set.is_none()) {
    for (auto s : set) o.sets.push_back(py::str(s).cast<std::string>());
  }
  // channels: {"depth": "Z"} or ["depth=Z", ...]
  if (py::isinstance<py::dict>(channels)) {
    for (auto [k, v] : channels.cast<py::dict>())
      o.channels.emplace_back(py::str(k).cast<std::string>(), py::str(v).cast<std::string>());
  } else if (!channels.is_none()) {
    for (auto c : channels) {
      const auto s = py::str(c).cast<std::string>();
      const auto eq = s.find('=');
      if (eq == std::string::npos) throw io::IoError("channels: " + s + ": expected ROLE=NAME");
      o.channels.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
  }
  return o;
}

// {name: 2-D array}; every array the same shape. float16 arrays are written back as half.
io::Image image_from_arrays(const py::dict& arrays) {
  io::Image img;
  std::string first;
  for (auto [k, v] : arrays) {
    const std::string name = py::str(k).cast<std::string>();
    const auto a = py::array::ensure(v);
    if (!a) throw io::IoError("channel " + name + ": not an array");
    if (a.ndim() != 2) {
      throw io::IoError("channel " + name + ": expected a 2-D array (height, width), got " +
                        std::to_string(a.ndim()) + " dimensions");
    }
    const int h = int(a.shape(0)), w = int(a.shape(1));
    if (first.empty()) {
      first = name;
      img.width = img.full_w = w;
      img.height = img.full_h = h;
    } else if (w != img.width || h != img.height) {
      throw io::IoError("channel " + name + ": " + std::to_string(h) + "x" + std::to_string(w) +
                        " differs from channel " + first + "'s " + std::to_string(img.height) +
                        "x" + std::to_string(img.width));
    }
    const bool half = a.dtype().kind() == 'f' && a.dtype().itemsize() == 2;
    const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!f) throw io::IoError("channel " + name + ": cannot be read as float32");
    img.channels.push_back({name, half ? io::Storage::half : io::Storage::f32,
                            std::vector<float>(f.data(), f.data() + f.size())});
  }
  if (first.empty()) throw io::IoError("channels: no arrays given");
  return img;
}

// Half channels come back as float16, rounded as the EXR writer rounds them (OIIO's converter),
// so an array is bitwise what the file written from the same image holds.
py::dict arrays_from_image(const io::Image& img) {
  py::dict d;
  const std::vector<py::ssize_t> shape{py::ssize_t(img.height), py::ssize_t(img.width)};
  for (const auto& c : img.channels) {
    if (c.storage == io::Storage::half) {
      py::array a(py::dtype("float16"), shape);
      OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, c.data.data(), OIIO::TypeDesc::HALF,
                                 a.mutable_data(), int(c.data.size()));
      d[py::str(c.name)] = a;
    } else {
      py::array_t<float> a(shape);
      std::copy(c.data.begin(), c.data.end(), a.mutable_data());
      d[py::str(c.name)] = a;
    }
  }
  return d;
}

bool is_arrays(const py::object& input) { return py::isinstance<py::dict>(input); }

run::LoadedFrame plan_of(const run::JobConfig& job, const py::object& input) {
  if (is_arrays(input)) return run::plan_image_frame(job, image_from_arrays(input), "arrays");
  const std::string path = py::str(input);
  py::gil_scoped_release nogil;
  return run::plan_frame(job, path);
}

py::dict roles_dict(const run::LoadedFrame& f) {
  std::vector<std::string> all = io::global_roles();
  for (const auto& l : f.roles.lights)
    for (const auto& s : io::light_role_suffixes()) all.push_back(l + "." + s);
  py::dict roles;
  for (const auto& r : all) {
    const auto* b = f.roles.get(r);
    roles[py::str(r)] =
        b ? py::object(py::dict("channels"_a = b->terms, "how"_a = b->how)) : py::none();
  }
  return py::dict("file"_a = f.input, "width"_a = f.img.width, "height"_a = f.img.height,
                  "channels"_a = f.img.channel_names(), "layer"_a = f.roles.layer,
                  "lights"_a = f.roles.lights,
                  "camera"_a = f.camera ? py::object(py::str(f.camera->source)) : py::none(),
                  "roles"_a = roles);
}

py::dict plan_dict(const run::LoadedFrame& f) {
  const auto& p = f.plan;
  py::list passes, resources, effects;
  for (const auto& s : p.passes)
    passes.append(py::dict("name"_a = s.name, "label"_a = s.label, "reads"_a = s.reads,
                           "writes"_a = s.writes, "light"_a = s.light));
  for (const auto& r : p.resources)
    resources.append(py::dict("name"_a = r.name, "planes"_a = r.planes, "upload"_a = r.upload,
                              "bytes"_a = r.bytes));
  for (const auto& e : p.effects)
    effects.append(
        py::dict("effect"_a = e.effect, "runs"_a = e.runs, "method"_a = e.method, "why"_a = e.why));
  return py::dict("width"_a = p.width, "height"_a = p.height, "passes"_a = passes,
                  "resources"_a = resources, "effects"_a = effects, "missing"_a = p.missing,
                  "gpu_bytes"_a = p.gpu_bytes(), "reach"_a = p.reach, "text"_a = p.describe());
}

void warn(const std::string& msg) { PyErr_WarnEx(PyExc_RuntimeWarning, msg.c_str(), 1); }

// One frame through the job-level stages `isg run` uses: load, process, write.
py::object run_frame(const py::object& input, const py::object& output, const run::JobConfig& job,
                     Context* context, const std::string& device) {
  std::optional<run::LoadedFrame> f;
  const bool arrays = is_arrays(input);
  std::string out_path;
  if (arrays) {
    auto img = image_from_arrays(input);
    py::gil_scoped_release nogil;
    f.emplace(run::load_image_frame(job, std::move(img), "arrays"));
  } else {
    if (output.is_none())
      throw io::IoError(py::str(input).cast<std::string>() + ": run needs an output file");
    const std::string in = py::str(input);
    out_path = py::str(output);
    py::gil_scoped_release nogil;
    io::check_writable(out_path, job.write);
    f.emplace(run::load_frame(job, in));
  }
  for (const auto& nf : f->nonfinite)
    warn(f->input + ": channel " + nf.channel + " had " + std::to_string(nf.count) +
         " NaN/Inf values, set to 0");
  run::Stats st;
  {
    py::gil_scoped_release nogil;
    std::unique_ptr<Context> own;
    if (!context) own = std::make_unique<Context>(device, false, false);
    st = run::process_frame(context ? context->get() : own->get(), job, *f);
    if (!arrays) run::write_frame(job, *f, out_path);
  }
  for (const auto& w : st.warnings) warn(w);
  if (arrays) return arrays_from_image(f->img);
  py::dict passes;
  for (const auto& t : st.passes) passes[py::str(t.name)] = t.ms;
  return py::dict("output"_a = out_path, "width"_a = f->img.width, "height"_a = f->img.height,
                  "channels"_a = f->img.channel_names(), "gpu_ms"_a = passes, "tiles"_a = st.tiles);
}

}  // namespace
}  // namespace isg::python

PYBIND11_MODULE(isg, m) {
  using namespace isg::python;
  m.doc() =
      "isg: soft shadows, glossy reflections and depth of field from a renderer's AOVs "
      "(the job-level entry points of `isg run`; see README.md, section Python)";
  m.attr("__version__") = ISG_VERSION;

  static py::exception<std::runtime_error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<isg::io::IoError> io_error(m, "IoError", error.ptr());
  static py::exception<isg::params::ParamError> param_error(m, "ParamError", error.ptr());
  static py::exception<isg::gpu::GpuError> gpu_error(m, "GpuError", error.ptr());
  // pybind11's translator type takes std::exception_ptr by value.
  py::register_exception_translator([](std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
    try {
      if (p) std::rethrow_exception(p);
    } catch (const isg::io::IoError& e) {
      io_error(e.what());
    } catch (const isg::params::ParamError& e) {
      param_error(e.what());
    } catch (const isg::gpu::GpuError& e) {
      gpu_error(e.what());
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const py::error_already_set&) {
      throw;
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const std::runtime_error& e) {
      error(e.what());
    }
  });

  py::class_<Context>(m, "Context", "A Vulkan device, set up once for many calls (context=...).")
      .def(py::init<const std::string&, bool, bool>(), "device"_a = "", "require_gpu"_a = false,
           "validation"_a = false)
      .def_property_readonly("device", &Context::device);

  // The keyword arguments every call takes, as `isg run` spells them.
#define ISG_JOB_ARGS                                                                              \
  py::kw_only(), "scene"_a = py::none(), "preset"_a = py::none(), "set"_a = py::none(),           \
                 "channels"_a = py::none(), "layer"_a = py::none(), "compression"_a = py::none(), \
                 "input_colorspace"_a = py::none()

  m.def(
      "roles",
      [](const py::object& input, const py::object& scene, const py::object& preset,
         const py::object& set, const py::object& channels, const py::object& layer,
         const py::object& compression, const py::object& cs) {
        const auto job =
            make_job(options(scene, preset, set, channels, layer, compression, cs, false));
        return roles_dict(plan_of(job, input));
      },
      "input"_a, ISG_JOB_ARGS,
      "The channel roles found in an EXR file (or a dict of arrays), as `isg info --json`.");
  m.def(
      "plan",
      [](const py::object& input, const py::object& scene, const py::object& preset,
         const py::object& set, const py::object& channels, const py::object& layer,
         const py::object& compression, const py::object& cs) {
        const auto job =
            make_job(options(scene, preset, set, channels, layer, compression, cs, false));
        return plan_dict(plan_of(job, input));
      },
      "input"_a, ISG_JOB_ARGS,
      "The plan `isg run --dry-run` prints: passes, resources, effects and why, missing roles.");
  m.def(
      "run",
      [](const py::object& input, const py::object& output, const py::object& scene,
         const py::object& preset, const py::object& set, const py::object& channels,
         const py::object& layer, const py::object& compression, const py::object& cs,
         bool no_clobber, Context* context, const std::string& device) {
        const auto job =
            make_job(options(scene, preset, set, channels, layer, compression, cs, no_clobber));
        return run_frame(input, output, job, context, device);
      },
      "input"_a, "output"_a = py::none(), ISG_JOB_ARGS, "no_clobber"_a = false,
      "context"_a = nullptr, "device"_a = "",
      "Runs isg on one frame. input: an EXR path (writes `output`, returns what ran) or a dict "
      "{channel name: 2-D array} (returns every channel, the composite in R G B A, as float32 "
      "arrays). Bitwise what `isg run` computes with the same options.");
#undef ISG_JOB_ARGS

  m.def(
      "read_exr",
      [](const py::object& path) {
        const std::string p = py::str(path);
        isg::io::Image img;
        {
          py::gil_scoped_release nogil;
          img = isg::io::read_exr(p);
        }
        return arrays_from_image(img);
      },
      "path"_a,
      "Every channel of an EXR file as {name: array (height, width)}, float16 for half channels.");
}
