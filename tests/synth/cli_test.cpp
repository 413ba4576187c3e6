// isg-synth end to end: the files it writes, and how it refuses bad input.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string err;
};

// Runs isg-synth with `args`, capturing stderr.
Result run(const std::string& args, const std::string& tag) {
  fs::create_directories(ISG_SYNTH_TMP);
  const fs::path err = fs::path(ISG_SYNTH_TMP) / (tag + ".stderr");
  const std::string cmd = std::string(ISG_SYNTH_EXE) + " " + args + " >/dev/null 2>" + err.string();
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream f(err);
  std::stringstream ss;
  ss << f.rdbuf();
  r.err = ss.str();
  return r;
}

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

TEST(SynthCli, WritesEveryFileInTheContractLayout) {
  const fs::path out = fs::path(ISG_SYNTH_TMP) / "pp";
  fs::remove_all(out);
  const Result r = run("parallel-planes --out " + out.string() +
                           " --width 48 --height 27 --ref-spp 4 --shadowmap-size 64 --threads 2",
                       "pp");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f :
       {"aovs.exr", "shadowmap_key.exr", "scene.json", "ref/softshadow_key.exr",
        "ref/softshadow_closed_form.exr", "ref/glossy.exr", "ref/dof.exr", "ref/beauty.exr"})
    EXPECT_TRUE(fs::exists(out / f)) << f;

  std::ifstream jf(out / "scene.json");
  const auto j = nlohmann::json::parse(jf);
  EXPECT_EQ(j["camera"]["width"], 48);
  EXPECT_EQ(j["camera"]["world_to_camera"].size(), 16u);
  const auto& l = j["lights"][0];
  EXPECT_EQ(l["name"], "key");
  EXPECT_EQ(l["type"], "disk");
  EXPECT_EQ(l["shadowmap"]["width"], 64);
  const double hfov = 2 * std::atan(j["camera"]["sensor_width_mm"].get<double>() /
                                    (2 * j["camera"]["focal_length_mm"].get<double>()));
  const double yfov = 2 * std::atan(std::tan(hfov / 2) * 27 / 48) * 180 / M_PI;
  EXPECT_NEAR(j["camera"]["yfov_deg"].get<double>(), yfov, 1e-9);
  for (const auto& [key, value] : j.items())
    EXPECT_TRUE(key == "units" || key == "scene_radius" || key == "camera" || key == "lights");

  auto in = OIIO::ImageInput::open((out / "aovs.exr").string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  for (const char* c : {"R",
                        "G",
                        "B",
                        "A",
                        "Z",
                        "P.X",
                        "P.Y",
                        "P.Z",
                        "N.X",
                        "N.Y",
                        "N.Z",
                        "roughness",
                        "key.shadow",
                        "key.occluder",
                        "key.direct.R",
                        "key.direct.G",
                        "key.direct.B",
                        "refl.R",
                        "refl.G",
                        "refl.B",
                        "refl.dist",
                        "refl.weight.R",
                        "refl.weight.G",
                        "refl.weight.B"})
    EXPECT_GE(spec.channelindex(c), 0) << c;
  EXPECT_LT(spec.channelindex("other.R"), 0);
  EXPECT_EQ(spec.channelformat(spec.channelindex("P.X")), OIIO::TypeDesc::FLOAT);
  // worldToCamera is the transpose (Imath row-vector convention) of scene.json's matrix.
  const OIIO::ParamValue* w2c = spec.find_attribute("worldToCamera", OIIO::TypeMatrix44);
  ASSERT_NE(w2c, nullptr);
  const float* m = static_cast<const float*>(w2c->data());
  for (int row = 0; row < 4; ++row)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(m[c * 4 + row], j["camera"]["world_to_camera"][size_t(row * 4 + c)].get<double>(),
                  1e-6);
  // worldToNDC (row vectors) takes a pixel's P to its pixel centre in [−1, 1]², +y up.
  const OIIO::ParamValue* w2n = spec.find_attribute("worldToNDC", OIIO::TypeMatrix44);
  ASSERT_NE(w2n, nullptr);
  const float* n = static_cast<const float*>(w2n->data());
  std::vector<float> px(size_t(spec.width) * spec.height * size_t(spec.nchannels));
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  const int ca = spec.channelindex("A"), cx = spec.channelindex("P.X"),
            cy = spec.channelindex("P.Y"), cz = spec.channelindex("P.Z");
  int checked = 0;
  for (int y = 0; y < spec.height; y += 3)
    for (int x = 0; x < spec.width; x += 3) {
      const float* p = &px[(size_t(y) * spec.width + x) * size_t(spec.nchannels)];
      if (p[ca] < 1) continue;
      const double P[4] = {p[cx], p[cy], p[cz], 1};
      double h[4] = {0, 0, 0, 0};
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) h[c] += P[k] * n[k * 4 + c];
      EXPECT_NEAR((h[0] / h[3] + 1) * 0.5 * spec.width, x + 0.5, 0.01);
      EXPECT_NEAR((1 - h[1] / h[3]) * 0.5 * spec.height, y + 0.5, 0.01);
      EXPECT_GT(h[2] / h[3], -1);
      EXPECT_LT(h[2] / h[3], 1);
      ++checked;
    }
  EXPECT_GT(checked, 20);

  auto ref = OIIO::ImageInput::open((out / "ref/softshadow_key.exr").string());
  ASSERT_TRUE(ref);
  EXPECT_EQ(ref->spec().get_int_attribute("isg:spp"), 4);
  EXPECT_EQ(ref->spec().get_string_attribute("isg:case"), "parallel-planes");
  EXPECT_NE(ref->spec().find_attribute("isg:render_seconds"), nullptr);
  EXPECT_GE(ref->spec().channelindex("mask"), 0);
  EXPECT_GE(ref->spec().channelindex("key.softshadow"), 0);
}

TEST(SynthCli, RejectsBadInputWithOneLine) {
  const std::string out = " --out " + (fs::path(ISG_SYNTH_TMP) / "bad").string();
  for (const auto& [args, needle] : std::vector<std::pair<std::string, std::string>>{
           {"no-such-scene" + out, "no-such-scene"},
           {"contact --width 0" + out, "--width"},
           {"contact --roughness 2" + out, "--roughness"},
           {"contact --light-radius -1" + out, "--light-radius"},
           {"sun --light-radius 0.2" + out, "--light-radius"},
           {"sun --sun-angle 0" + out, "--sun-angle"},
           {"contact --sun-angle 1" + out, "--sun-angle"},
           {"contact --width abc" + out, "--width"},
           {"contact --bogus" + out, "bogus"},
           {"contact", "--out"}}) {
    const Result r = run(args, "bad");
    EXPECT_NE(r.code, 0) << args;
    EXPECT_EQ(lines(r.err), 1u) << args << ": " << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(fs::path(ISG_SYNTH_TMP) / "bad" / "aovs.exr"));
}

// Each light of sun, spot and three-lights: its files, its AOV channels, and in scene.json
// exactly the contract's keys for its type (AOV_CONTRACT.md, input 3), its shadow map's too.
TEST(SynthCli, EveryLightInTheContractLayout) {
  using Keys = std::set<std::string>;
  const Keys perspective = {"file", "world_to_light", "projection", "yfov_deg", "near",
                            "far",  "width",          "height"};
  const Keys orthographic = {"file", "world_to_light", "projection", "width_m", "height_m", "near",
                             "far",  "width",          "height"};
  const std::map<std::string, Keys> light_keys = {
      {"sphere", {"name", "type", "position", "radius", "shadowmap"}},
      {"rect", {"name", "type", "position", "normal", "size", "u_axis", "shadowmap"}},
      {"spot",
       {"name", "type", "position", "radius", "normal", "spot_angle_deg", "spot_blend",
        "shadowmap"}},
      {"sun", {"name", "type", "direction", "angle_deg", "shadowmap"}}};
  const std::map<std::string, std::vector<std::pair<std::string, std::string>>> scenes = {
      {"sun", {{"sun", "sun"}}},
      {"spot", {{"spot", "spot"}}},
      {"three-lights", {{"key", "sphere"}, {"sun", "sun"}, {"fill", "rect"}}}};
  for (const auto& [scene, lights] : scenes) {
    const fs::path out = fs::path(ISG_SYNTH_TMP) / ("lights-" + scene);
    fs::remove_all(out);
    const Result r = run(scene + " --out " + out.string() +
                             " --width 32 --height 18 --ref-spp 1 --shadowmap-size 32 --threads 2" +
                             (scene == "spot" ? "" : " --sun-angle 1.5"),
                         "lights");
    ASSERT_EQ(r.code, 0) << scene << ": " << r.err;
    std::ifstream jf(out / "scene.json");
    const auto j = nlohmann::json::parse(jf);
    ASSERT_EQ(j["lights"].size(), lights.size()) << scene;
    auto in = OIIO::ImageInput::open((out / "aovs.exr").string());
    ASSERT_TRUE(in);
    for (size_t i = 0; i < lights.size(); ++i) {
      const auto& [name, type] = lights[i];
      const auto& l = j["lights"][i];
      EXPECT_EQ(l["name"], name);
      EXPECT_EQ(l["type"], type);
      Keys keys, map_keys;
      for (const auto& [k, v] : l.items()) keys.insert(k);
      for (const auto& [k, v] : l["shadowmap"].items()) map_keys.insert(k);
      EXPECT_EQ(keys, light_keys.at(type)) << scene << " " << name;
      EXPECT_EQ(map_keys, type == "sun" ? orthographic : perspective) << scene << " " << name;
      EXPECT_EQ(l["shadowmap"]["file"], "shadowmap_" + name + ".exr");
      EXPECT_EQ(l["shadowmap"]["projection"], type == "sun" ? "orthographic" : "perspective");
      if (type == "sun") {
        EXPECT_EQ(l["angle_deg"], 1.5);
        EXPECT_EQ(l["shadowmap"]["near"], 0.0);
      }
      for (const std::string& f : {"shadowmap_" + name + ".exr", "ref/softshadow_" + name + ".exr"})
        EXPECT_TRUE(fs::exists(out / f)) << scene << " " << f;
      for (const char* c : {".shadow", ".occluder", ".direct.R", ".direct.G", ".direct.B"})
        EXPECT_GE(in->spec().channelindex(name + c), 0) << scene << " " << name << c;
      auto ref = OIIO::ImageInput::open((out / "ref" / ("softshadow_" + name + ".exr")).string());
      ASSERT_TRUE(ref);
      EXPECT_EQ(ref->spec().nchannels, 2);
      EXPECT_GE(ref->spec().channelindex(name + ".softshadow"), 0);
      EXPECT_GE(ref->spec().channelindex("mask"), 0);
    }
    EXPECT_EQ(in->spec().nchannels, 19 + 5 * int(lights.size())) << scene;
    EXPECT_FALSE(fs::exists(out / "shadowmap_key.exr") && lights[0].first != "key") << scene;
  }
}

TEST(SynthCli, ListsScenes) {
  const fs::path out = fs::path(ISG_SYNTH_TMP) / "list.txt";
  ASSERT_EQ(std::system((std::string(ISG_SYNTH_EXE) + " --list >" + out.string()).c_str()), 0);
  std::ifstream f(out);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  for (const char* s : {"parallel-planes", "contact", "stack", "gloss", "dof", "far-world",
                        "grazing", "depth-range", "sun", "spot", "three-lights"})
    EXPECT_NE(text.find(s), std::string::npos) << s;
}

}  // namespace
