// Files: the EXRs, scene.json, and generate() tying the renders together.
#include <OpenImageIO/imageio.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "synth.h"

namespace isg::synth {
namespace {

namespace fs = std::filesystem;
using OIIO::TypeDesc;

struct Attr {
  std::string name;
  enum class Kind { i, f, s, m44 } kind;
  int i = 0;
  double f = 0;
  std::string s;
  std::array<float, 16> m{};
};

// OpenEXR/Imath matrices act on row vectors (p' = p·M): the transpose of scene.json's
// row-major column-vector matrices.
Attr matrix_attr(const std::string& name, const std::array<double, 16>& column_vector) {
  Attr a{name, Attr::Kind::m44};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      a.m[size_t(c) * 4 + size_t(r)] = float(column_vector[size_t(r) * 4 + size_t(c)]);
  return a;
}

// Z, P and the shadow map in float32; everything else half. Written to a temporary name
// and renamed, so a failure leaves no partial file.
void write_exr(const fs::path& path, const Image& img, const std::vector<Attr>& attrs,
               const std::set<std::string>& skip = {}) {
  static const std::set<std::string> float_channels = {"Z", "P.X", "P.Y", "P.Z"};
  std::vector<int> keep;
  for (size_t c = 0; c < img.channels.size(); ++c)
    if (!skip.count(img.channels[c])) keep.push_back(int(c));
  OIIO::ImageSpec spec(img.width, img.height, int(keep.size()), TypeDesc::HALF);
  spec.channelnames.clear();
  spec.channelformats.clear();
  for (int c : keep) {
    const std::string& name = img.channels[size_t(c)];
    spec.channelnames.push_back(name);
    spec.channelformats.push_back(float_channels.count(name) ? TypeDesc::FLOAT : TypeDesc::HALF);
  }
  spec.alpha_channel = -1;
  spec.z_channel = -1;
  spec.attribute("compression", "zip");
  for (const Attr& a : attrs) {
    switch (a.kind) {
      case Attr::Kind::i:
        spec.attribute(a.name, a.i);
        break;
      case Attr::Kind::f:
        spec.attribute(a.name, float(a.f));
        break;
      case Attr::Kind::s:
        spec.attribute(a.name, a.s);
        break;
      case Attr::Kind::m44:
        spec.attribute(a.name, OIIO::TypeMatrix44, a.m.data());
        break;
    }
  }
  std::vector<float> data(size_t(img.width) * img.height * keep.size());
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    for (size_t k = 0; k < keep.size(); ++k)
      data[p * keep.size() + k] = img.pixels[p * img.channels.size() + size_t(keep[k])];
  const fs::path tmp = path.string() + ".part";
  auto out = OIIO::ImageOutput::create("openexr");
  if (!out) throw std::runtime_error(path.string() + ": cannot create an EXR writer");
  if (!out->open(tmp.string(), spec) || !out->write_image(TypeDesc::FLOAT, data.data()) ||
      !out->close()) {
    const std::string err = out->geterror();
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": " + err);
  }
  fs::rename(tmp, path);
}

nlohmann::ordered_json matrix_json(const std::array<double, 16>& m) {
  auto j = nlohmann::ordered_json::array();
  for (double v : m) j.push_back(v);
  return j;
}

nlohmann::ordered_json vec_json(Vec3 v) { return {v.x, v.y, v.z}; }

const char* light_type(Light::Type t) {
  switch (t) {
    case Light::Type::sphere:
      return "sphere";
    case Light::Type::disk:
      return "disk";
    case Light::Type::rect:
      return "rect";
    case Light::Type::spot:
      return "spot";
    case Light::Type::sun:
      return "sun";
  }
  return "sphere";
}

void write_scene_json(const fs::path& path, const Scene& s, int shadowmap_size) {
  nlohmann::ordered_json j;
  const Camera& c = s.camera;
  j["units"] = "m";
  j["scene_radius"] = scene_radius(s);
  j["camera"] = {{"world_to_camera", matrix_json(world_to_camera(c))},
                 {"projection", "perspective"},
                 {"yfov_deg", yfov_deg(c)},
                 {"width", c.width},
                 {"height", c.height},
                 {"near", c.near},
                 {"far", c.far},
                 {"focus_distance", c.focus_distance},
                 {"fstop", c.fstop},
                 {"focal_length_mm", c.focal_length_mm},
                 {"sensor_width_mm", c.sensor_width_mm}};
  auto lights = nlohmann::ordered_json::array();
  for (size_t i = 0; i < s.lights.size(); ++i) {
    const Light& k = s.lights[i];
    const bool sun = k.type == Light::Type::sun;
    nlohmann::ordered_json l;
    l["name"] = k.name;
    l["type"] = light_type(k.type);
    if (sun) {
      l["direction"] = vec_json(k.direction);
      l["angle_deg"] = k.angle_deg;
    } else {
      l["position"] = vec_json(k.position);
    }
    if (k.type == Light::Type::sphere || k.type == Light::Type::disk || k.type == Light::Type::spot)
      l["radius"] = k.radius;
    if (k.type == Light::Type::disk || k.type == Light::Type::rect || k.type == Light::Type::spot)
      l["normal"] = vec_json(k.normal);
    if (k.type == Light::Type::rect) {
      l["size"] = {k.size_u, k.size_v};
      l["u_axis"] = vec_json(k.u_axis);
    }
    if (k.type == Light::Type::spot) {
      l["spot_angle_deg"] = k.spot_angle_deg;
      l["spot_blend"] = k.spot_blend;
    }
    const ShadowMapView v = shadowmap_view(s, i);
    nlohmann::ordered_json m;
    m["file"] = "shadowmap_" + k.name + ".exr";
    m["world_to_light"] = matrix_json(v.world_to_light);
    if (v.orthographic) {
      m["projection"] = "orthographic";
      m["width_m"] = v.width_m;
      m["height_m"] = v.height_m;
      m["near"] = v.near;
      m["far"] = v.far;
    } else {
      m["projection"] = "perspective";
      m["yfov_deg"] = v.yfov_deg;
      m["near"] = v.near;
      m["far"] = v.far;
    }
    m["width"] = shadowmap_size;
    m["height"] = shadowmap_size;
    l["shadowmap"] = m;
    lights.push_back(l);
  }
  j["lights"] = lights;
  const fs::path tmp = path.string() + ".part";
  {
    std::ofstream f(tmp);
    f << j.dump(2) << "\n";
    if (!f) throw std::runtime_error(path.string() + ": cannot write");
  }
  fs::rename(tmp, path);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::vector<Timing> generate(const Options& opts, const fs::path& out_dir) {
  const Scene s = build_scene(opts);
  std::vector<Timing> times;
  std::error_code ec;
  fs::create_directories(out_dir / (opts.refs ? "ref" : ""), ec);
  if (ec) throw std::runtime_error(out_dir.string() + ": " + ec.message());
  using clock = std::chrono::steady_clock;

  auto t0 = clock::now();
  const Image aovs = render_aovs(s, opts);
  write_exr(out_dir / "aovs.exr", aovs,
            {matrix_attr("worldToCamera", world_to_camera(s.camera)),
             matrix_attr("worldToNDC", world_to_ndc(s.camera)),
             {"isg:case", Attr::Kind::s, 0, 0, s.name},
             {"isg:source", Attr::Kind::s, 0, 0, "isg-synth"},
             {"isg:aov_spp", Attr::Kind::i, opts.aov_spp},
             {"isg:frame", Attr::Kind::i, opts.frame}},
            {"other.R", "other.G", "other.B"});
  times.push_back({"aovs.exr", seconds_since(t0)});

  for (size_t i = 0; i < s.lights.size(); ++i) {
    t0 = clock::now();
    const std::string file = "shadowmap_" + s.lights[i].name + ".exr";
    write_exr(out_dir / file, render_shadowmap(s, opts.shadowmap_size, i),
              {{"isg:case", Attr::Kind::s, 0, 0, s.name}});
    times.push_back({file, seconds_since(t0)});
  }
  write_scene_json(out_dir / "scene.json", s, opts.shadowmap_size);
  if (!opts.refs) return times;

  // isg:light_radius: the light's (rect: half its u size); a sun has isg:light_angle_deg instead.
  auto size_attr = [](const Light& l) -> Attr {
    if (l.type == Light::Type::sun) return {"isg:light_angle_deg", Attr::Kind::f, 0, l.angle_deg};
    return {"isg:light_radius", Attr::Kind::f, 0,
            l.type == Light::Type::rect ? l.size_u / 2 : l.radius};
  };
  auto ref = [&](const std::string& file, auto&& render, MaskKind mask, int spp, size_t light = 0) {
    const auto r0 = clock::now();
    Image img = render();
    const double secs = seconds_since(r0);
    add_mask(img, aovs, mask, s.lights[light].name);
    write_exr(out_dir / "ref" / file, img,
              {{"isg:spp", Attr::Kind::i, spp},
               {"isg:render_seconds", Attr::Kind::f, 0, secs},
               {"isg:case", Attr::Kind::s, 0, 0, s.name},
               size_attr(s.lights[light]),
               {"isg:fstop", Attr::Kind::f, 0, s.camera.fstop},
               {"isg:thin_lens", Attr::Kind::i, s.depth_of_field ? 1 : 0}});
    times.push_back({"ref/" + file, secs});
  };
  const int spp = opts.ref_spp;
  for (size_t i = 0; i < s.lights.size(); ++i) {
    ref(
        "softshadow_" + s.lights[i].name + ".exr",
        [&] { return render_softshadow(s, opts, spp, i); }, MaskKind::softshadow, spp, i);
  }
  if (s.parallel_planes) {
    ref(
        "softshadow_closed_form.exr", [&] { return render_softshadow_closed_form(s, opts); },
        MaskKind::softshadow, 1);
  }
  ref(
      "glossy.exr", [&] { return render_glossy(s, opts, spp); }, MaskKind::glossy, spp);
  ref(
      "dof.exr", [&] { return render_dof(s, opts, spp); }, MaskKind::foreground, spp);
  ref(
      "beauty.exr", [&] { return render_beauty_ref(s, opts, spp); }, MaskKind::foreground, spp);
  return times;
}

}  // namespace isg::synth
