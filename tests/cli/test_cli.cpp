// End to end: the `isg` binary on files the tests write, and on the shared Blender case.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/image.h"
#include "io/scene.h"
#include "support/command.h"
#include "support/images.h"

namespace fs = std::filesystem;

namespace {

using Result = isg::test::CommandResult;

Result run_isg(const std::string& args) {
  return isg::test::run_command(std::string(ISG_BINARY) + " " + args);
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

const char* kScene = R"({"scene_radius": 3.0, "lights": [{"name": "key", "type": "sphere",
  "position": [0, 0, 5], "radius": 0.2}]})";

// The one-line error contract: non-zero exit, one line on stderr naming `needle`, no output.
void expect_clean_failure(const Result& r, const std::string& needle, const fs::path& out) {
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.err.find("isg: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr: " << r.err;
  size_t lines = std::count(r.err.begin(), r.err.end(), '\n');
  EXPECT_EQ(lines, 1u) << r.err;
  EXPECT_FALSE(fs::exists(out)) << out;
  std::error_code ec;
  if (!fs::is_directory(out.parent_path(), ec)) return;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left " << e.path();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = isg::test::temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
    in = dir / "aovs.exr";
    isg::io::write_exr(in, isg::test::contract_aovs(24, 16), {});
    scene = dir / "scene.json";
    std::ofstream(scene) << kScene;
    out = dir / "out.exr";
  }
  fs::path dir, in, scene, out;
};

}  // namespace

TEST_F(Cli, RunWritesEveryChannelPlusProvenance) {
  // Method `hard` has a closed form (soft == hard, composite == beauty); the default is `isg`.
  auto r = run_isg(std::string("run ") + q(in) + " --scene " + q(scene) + " -o " + q(out) +
                   " --timings --set shadows.method=hard");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + out.string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("composite[key]"), std::string::npos) << r.out;  // per-pass GPU time
  auto a = isg::io::read_exr(in), b = isg::io::read_exr(out);
  for (const auto& c : a.channels) {
    std::string name = (c.name.size() == 1 && std::string("RGBA").find(c.name) != std::string::npos)
                           ? "input." + c.name : c.name;
    const auto* o = b.find(name);
    ASSERT_TRUE(o) << name;
    EXPECT_EQ(o->data, c.data) << name;
  }
  ASSERT_TRUE(b.find("key.softshadow"));
  // Method `hard`: soft == hard, so the composite is the beauty itself.
  EXPECT_EQ(b.find("key.softshadow")->data, a.find("key.shadow")->data);
  for (const char* c : {"R", "G", "B", "A"}) EXPECT_EQ(b.find(c)->data, a.find(c)->data) << c;
  EXPECT_EQ(b.attributes.get_string("isg:param:shadows.method"), "hard");
  EXPECT_FALSE(b.attributes.get_string("isg:device").empty());
  EXPECT_FALSE(b.attributes.get_string("isg:version").empty());
}

// input.positions=Z: the plan reads depth instead of P, and the output says so (isg:positions);
// the default P leaves both as they were.
TEST_F(Cli, PositionsFromDepthAreChosenAndRecorded) {
  const fs::path sample = fs::path(ISG_SOURCE_DIR) / "samples" / "contact";
  const std::string base = std::string("run ") + q(sample / "aovs.exr") + " --scene " +
                           q(sample / "scene.json") + " --set shadows.method=isg";
  for (const bool z : {false, true}) {
    const std::string set = z ? " --set input.positions=Z" : "";
    auto plan = run_isg(base + set + " --dry-run");
    ASSERT_EQ(plan.code, 0) << plan.err;
    const auto line = plan.out.substr(plan.out.find("shadows.isg[key]"));
    const auto reads = line.substr(0, line.find('\n'));
    EXPECT_EQ(reads.find("position") != std::string::npos, !z) << reads;
    EXPECT_EQ(reads.find("depth") != std::string::npos, z) << reads;
    const fs::path o = dir / (z ? "z.exr" : "p.exr");
    auto r = run_isg(base + set + " -o " + q(o));
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string note = isg::io::read_exr(o).attributes.get_string("isg:positions");
    EXPECT_EQ(note.rfind("Z and the camera (input.positions=Z", 0) == 0, z) << note;
    EXPECT_EQ(note.empty(), !z) << note;
  }
}

TEST_F(Cli, RunsAreBitwiseIdentical) {
  for (const char* o : {"a.exr", "b.exr"}) {
    auto r = run_isg(std::string("run ") + q(in) + " --scene " + q(scene) + " -o " + q(dir / o));
    ASSERT_EQ(r.code, 0) << r.err;
  }
  auto a = isg::io::read_exr(dir / "a.exr"), b = isg::io::read_exr(dir / "b.exr");
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (const auto& c : a.channels) {
    ASSERT_TRUE(b.find(c.name)) << c.name;
    EXPECT_EQ(std::memcmp(c.data.data(), b.find(c.name)->data.data(), c.data.size() * sizeof(float)), 0) << c.name;
  }
}

TEST_F(Cli, InfoFindsRolesAndSaysWhatCanRun) {
  auto r = run_isg(std::string("info ") + q(in) + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["roles"]["beauty"]["how"], "contract name");
  EXPECT_TRUE(j["roles"]["key.shadow"].is_object());
  EXPECT_TRUE(j["roles"]["refl"].is_null());
  EXPECT_TRUE(j["effects"]["shadows[key]"]["can_run"].get<bool>());
  EXPECT_FALSE(j["effects"]["reflections"]["can_run"].get<bool>());
  EXPECT_NE(j["effects"]["reflections"]["why"].get<std::string>().find("refl"), std::string::npos);
  // What shadows.method = auto would pick: isg, no scene file giving the light a shadow map.
  EXPECT_EQ(j["effects"]["shadows[key]"]["auto"]["method"], "isg");
  EXPECT_NE(j["effects"]["shadows[key]"]["auto"]["why"].get<std::string>().find("not in the scene file"), std::string::npos);
}

TEST_F(Cli, CompareReportsClosedFormMetrics) {
  auto a = isg::test::make_image(8, 8, {"R", "mask"}, [](const std::string& n, int x, int) {
    return n == "mask" ? float(x < 4) : 0.25f;
  });
  auto b = isg::test::make_image(8, 8, {"R", "mask"}, [](const std::string& n, int x, int) {
    return n == "mask" ? float(x < 4) : (x < 4 ? 0.5f : 1.0f);
  });
  isg::io::write_exr(dir / "a.exr", a, {});
  isg::io::write_exr(dir / "b.exr", b, {});
  auto r = run_isg("compare " + q(dir / "a.exr") + " " + q(dir / "b.exr") + " --mask mask --json");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["all"]["pixels"], 32);
  EXPECT_NEAR(j["all"]["rmse"].get<double>(), 0.25, 1e-9);
  EXPECT_NEAR(j["all"]["max_abs"].get<double>(), 0.25, 1e-9);
}

TEST_F(Cli, CompareMaskFromAThirdFileAndHeatmap) {
  auto a = isg::test::make_image(8, 4, {"R"}, [](auto&, int, int) { return 0.0f; });
  auto b = isg::test::make_image(8, 4, {"R"}, [](auto&, int x, int) { return x < 4 ? 0.1f : 0.3f; });
  auto m = isg::test::make_image(8, 4, {"mask"}, [](auto&, int x, int) { return float(x >= 4); });
  isg::io::write_exr(dir / "a.exr", a, {});
  isg::io::write_exr(dir / "b.exr", b, {});
  isg::io::write_exr(dir / "m.exr", m, {});
  auto r = run_isg("compare " + q(dir / "a.exr") + " " + q(dir / "b.exr") + " --json --mask " +
                   q(dir / "m.exr") + ":mask --heatmap " + q(dir / "h.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["all"]["pixels"], 16);
  EXPECT_NEAR(j["all"]["rmse"].get<double>(), 0.3, 1e-6);
  auto h = isg::io::read_exr_header(dir / "m.exr");  // the mask file is untouched
  EXPECT_EQ(h.width, 8);
  EXPECT_TRUE(fs::exists(dir / "h.png"));
  EXPECT_GT(fs::file_size(dir / "h.png"), 50u);
}

TEST_F(Cli, DryRunPrintsThePlanAndWritesNothing) {
  auto r = run_isg(std::string("run ") + q(in) + " -o " + q(out) + " --dry-run --set shadows.method=none");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("shadows[key]: skipped: shadows.method = none"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("key.shadow:"), std::string::npos) << r.out;  // nothing allocated for it
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(Cli, PrintPresetShowsEveryParameter) {
  auto r = run_isg("run --print-preset --preset preview --set limits.max_channels=77");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("compression = \"zips\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max_channels = 77"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[shadows]"), std::string::npos);
}

TEST(CliDocs, ParametersDocMatchesTheTable) {
  // docs/parameters.md is generated from the parameter table; regenerate it with
  //   build/cli/isg params --markdown > docs/parameters.md
  auto r = run_isg("params --markdown");
  ASSERT_EQ(r.code, 0) << r.err;
  std::stringstream doc;
  doc << std::ifstream(std::string(ISG_SOURCE_DIR) + "/docs/parameters.md").rdbuf();
  EXPECT_EQ(doc.str(), r.out) << "docs/parameters.md is stale: regenerate it";
}

TEST_F(Cli, NanAndInfAreSanitisedAndCounted) {
  auto img = isg::test::contract_aovs(24, 16);
  img.find("key.direct.G")->data[5] = NAN;
  img.find("key.direct.G")->data[6] = INFINITY;
  isg::io::write_exr(in, img, {});
  auto r = run_isg(std::string("run ") + q(in) + " -o " + q(out));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("key.direct.G had 2 NaN/Inf values"), std::string::npos) << r.err;
  auto b = isg::io::read_exr(out);
  for (const auto& c : b.channels)
    for (float v : c.data) ASSERT_TRUE(std::isfinite(v)) << c.name;
}

TEST_F(Cli, BadInputsFailCleanly) {
  std::string o = " -o " + q(out);
  expect_clean_failure(run_isg("run " + q(dir / "nope.exr") + o), "nope.exr: no such file", out);
  std::ofstream(dir / "text.exr") << "not an exr";
  expect_clean_failure(run_isg("run " + q(dir / "text.exr") + o), "text.exr: not an OpenEXR file", out);
  // Truncated inside the pixel data.
  isg::io::write_exr(dir / "full.exr", isg::test::contract_aovs(64, 64), {"none", false});
  fs::copy_file(dir / "full.exr", dir / "cut.exr");
  fs::resize_file(dir / "cut.exr", fs::file_size(dir / "full.exr") * 3 / 4);
  expect_clean_failure(run_isg("run " + q(dir / "cut.exr") + o), "cut.exr", out);
  // Missing required channels.
  auto nob = isg::test::make_image(8, 8, {"Z"}, [](auto&, int, int) { return 1.f; });
  isg::io::write_exr(dir / "nobeauty.exr", nob, {});
  expect_clean_failure(run_isg("run " + q(dir / "nobeauty.exr") + o), "beauty", out);
  // Unwritable output.
  fs::create_directories(dir / "ro");
  ::chmod((dir / "ro").c_str(), 0555);
  if (::access((dir / "ro").c_str(), W_OK) != 0) {  // root can write anywhere
    expect_clean_failure(run_isg("run " + q(in) + " -o " + q(dir / "ro" / "o.exr")), "not writable",
                         dir / "ro" / "o.exr");
  }
  expect_clean_failure(run_isg("run " + q(in) + " -o " + q(dir / "nodir" / "o.exr")), "does not exist",
                       dir / "nodir" / "o.exr");
  // Bad preset values, bad --set, bad scene file, unknown role.
  std::ofstream(dir / "bad.toml") << "[output]\ncompression = \"jpeg\"\n";
  expect_clean_failure(run_isg("run " + q(in) + o + " --preset " + q(dir / "bad.toml")), "bad.toml:2", out);
  expect_clean_failure(run_isg("run " + q(in) + o + " --set shadows.method=magic"), "shadows.method", out);
  expect_clean_failure(run_isg("run " + q(in) + o + " --set nope.key=1"), "nope.key", out);
  std::ofstream(dir / "bad.json") << R"({"scene_radius": 1, "lights": [{"name": "key", "type": "sphere", "position": [0,0,1], "radius": -2}]})";
  expect_clean_failure(run_isg("run " + q(in) + o + " --scene " + q(dir / "bad.json")), "lights[0].radius", out);
  expect_clean_failure(run_isg("run " + q(in) + o + " --channel colour=R"), "unknown role colour", out);
  // The input is never overwritten.
  auto before = fs::file_size(in);
  auto r = run_isg("run " + q(in) + " -o " + q(in));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("is the input file"), std::string::npos) << r.err;
  EXPECT_EQ(fs::file_size(in), before);
}

TEST_F(Cli, NoClobberKeepsAnExistingOutput) {
  std::ofstream(out) << "precious";
  auto r = run_isg(std::string("run ") + q(in) + " -o " + q(out) + " --no-clobber");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--no-clobber"), std::string::npos) << r.err;
  std::stringstream s;
  s << std::ifstream(out).rdbuf();
  EXPECT_EQ(s.str(), "precious");
}

TEST_F(Cli, FrameSequenceResumesAndKeepsGoing) {
  for (int f = 1001; f <= 1006; ++f) {
    isg::io::write_exr(dir / ("shot." + std::to_string(f) + ".exr"), isg::test::contract_aovs(24, 16, unsigned(f)), {});
  }
  // Frame 1004 is damaged: cut inside its pixel data.
  auto bad = dir / "shot.1004.exr";
  fs::resize_file(bad, fs::file_size(bad) * 2 / 3);
  std::string args = "run " + q(dir / "shot.####.exr") + " -o " + q(dir / "out.%04d.exr") + " --scene " + q(scene);
  // Without --keep-going the run stops at the bad frame: exit 1, frames before it written.
  auto r = run_isg(args + " --frames 1001-1006");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("frame 1004"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out.1003.exr"));
  EXPECT_FALSE(fs::exists(dir / "out.1005.exr"));
  // Resume with --skip-existing --keep-going: 1001-1003 skipped, 1004 reported, the rest written.
  auto before = fs::last_write_time(dir / "out.1001.exr");
  r = run_isg(args + " --frames 1001-1006 --skip-existing --keep-going");
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.out.find("2 written, 3 skipped (existing), 1 failed"), std::string::npos) << r.out;
  EXPECT_EQ(fs::last_write_time(dir / "out.1001.exr"), before);
  EXPECT_TRUE(fs::exists(dir / "out.1005.exr"));
  EXPECT_TRUE(fs::exists(dir / "out.1006.exr"));
  EXPECT_FALSE(fs::exists(dir / "out.1004.exr"));
  // Each output is the same as a single-frame run of its input.
  r = run_isg("run " + q(dir / "shot.1006.exr") + " -o " + q(dir / "single.exr") + " --scene " + q(scene));
  ASSERT_EQ(r.code, 0) << r.err;
  auto seq = isg::io::read_exr(dir / "out.1006.exr"), one = isg::io::read_exr(dir / "single.exr");
  for (const auto& c : one.channels) EXPECT_EQ(seq.find(c.name)->data, c.data) << c.name;
  // Stepped ranges.
  r = run_isg(args + " --frames 1001-1005x2 --skip-existing");
  EXPECT_EQ(r.code, 0) << r.err;
  r = run_isg(args + " --frames 7-3");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--frames 7-3"), std::string::npos) << r.err;
}

TEST(CliShared, InfoFindsContractAndCyclesRoles) {
  auto c = isg::test::shared_case("contact");
  if (c.empty()) GTEST_SKIP() << "../shared/cases/contact is absent";
  auto a = nlohmann::json::parse(run_isg("info " + q(c / "aovs.exr") + " --json").out);
  auto b = nlohmann::json::parse(run_isg("info " + q(c / "cycles_native.exr") + " --json").out);
  for (const char* role : {"beauty", "depth", "position", "normal"}) {
    EXPECT_TRUE(a["roles"][role].is_object()) << role;
    EXPECT_TRUE(b["roles"][role].is_object()) << role;
  }
  for (const char* role : {"key.shadow", "key.occluder", "key.direct"}) EXPECT_TRUE(a["roles"][role].is_object()) << role;
  EXPECT_EQ(b["layer"], "ViewLayer");
}

TEST(CliShared, RunOnTheContactCase) {
  auto c = isg::test::shared_case("contact");
  if (c.empty()) GTEST_SKIP() << "../shared/cases/contact is absent";
  auto dir = isg::test::temp_dir("shared-run");
  auto r = run_isg("run --scene " + q(c / "scene.json") + " " + q(c / "aovs.exr") + " -o " + q(dir / "o.exr"));
  ASSERT_EQ(r.code, 0) << r.err;
  auto in = isg::io::read_exr_header(c / "aovs.exr");
  auto out = isg::io::read_exr(dir / "o.exr");
  EXPECT_GE(out.channels.size(), in.channels.size() + 5);  // + input.RGBA, key.softshadow
  EXPECT_EQ(out.attributes.get_string("isg:case"), "contact");  // input attributes kept
}

// isg-synth writes worldToNDC in the OpenGL convention ([-1,1], y up); Blender-free pipelines
// may write OpenEXR's [0,1]. Either way the camera read from the header must project like the
// scene file's camera.
TEST(CliSynth, CameraFromTheSynthHeaderMatchesItsSceneFile) {
  auto dir = isg::test::temp_dir("synth_camera");
  std::string cmd = std::string(ISG_SYNTH_BINARY) + " contact --out " + q(dir) +
                    " --width 64 --height 36 --no-refs --threads 2 >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  auto from_header = isg::io::camera_from_header(isg::io::read_exr(dir / "aovs.exr"));
  auto scene = isg::io::read_scene(dir / "scene.json");
  ASSERT_TRUE(from_header);
  ASSERT_TRUE(scene.camera);
  EXPECT_NEAR(from_header->yfov_deg, scene.camera->yfov_deg, 1e-3);
  for (isg::io::Vec3 p : {isg::io::Vec3{0, 0, 0}, isg::io::Vec3{0.5, 0.2, -0.3}, isg::io::Vec3{-1, 0.1, 0.7}}) {
    auto a = from_header->project(p), b = scene.camera->project(p);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-3) << i;
  }
}

// 1e5 and 1e6 m from the origin (isg-synth far-world, far-world-1e6) P's float32 step is wider
// than a 16th of a pixel at a scene radius (0.14 and 1.1 pixels at 160x90): `isg info` and `isg
// run` both take P refitted into a planar depth and say so (info's positions, the output's
// isg:positions; Z refitted with input.positions=Z), the refit is not an output, and auto then
// picks the map's pcss for this overhead light; at the origin nothing is refitted.
TEST(CliSynth, FarFromTheOriginPIsRefittedAndSaidSo) {
  auto dir = isg::test::temp_dir("synth_refit");
  for (const char* scene : {"contact", "far-world", "far-world-1e6"}) {
    std::string cmd = std::string(ISG_SYNTH_BINARY) + " " + scene + " --out " + q(dir / scene) +
                      " --width 160 --height 90 --no-refs --threads 2 >/dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  for (const char* scene : {"contact", "far-world", "far-world-1e6"}) {
    const bool far = std::string(scene) != "contact";
    const fs::path d = dir / scene;
    const std::string args = q(d / "aovs.exr") + " --scene " + q(d / "scene.json");
    auto info = run_isg("info " + args + " --json");
    ASSERT_EQ(info.code, 0) << info.err;
    const auto j = nlohmann::json::parse(info.out);
    const std::string pos = j["positions"];
    EXPECT_EQ(pos.rfind("P refitted", 0) == 0, far) << pos;
    if (!far) {
      EXPECT_EQ(pos, "P");
    }
    EXPECT_EQ(j["effects"]["shadows[key]"]["auto"]["method"], "pcss") << scene;
    for (const bool z : {false, true}) {
      const fs::path o = d / (z ? "z.exr" : "p.exr");
      auto r = run_isg("run " + args + " -o " + q(o) + (z ? " --set input.positions=Z" : ""));
      ASSERT_EQ(r.code, 0) << r.err;
      const auto out = isg::io::read_exr(o);
      const std::string note = out.attributes.get_string("isg:positions");
      EXPECT_EQ(note.rfind("P refitted", 0) == 0, far && !z) << scene << ": " << note;
      EXPECT_EQ(note.rfind("Z and the camera", 0) == 0, z && !far) << scene << ": " << note;
      EXPECT_EQ(note.rfind("Z refitted", 0) == 0, z && far) << scene << ": " << note;
      EXPECT_FALSE(out.find("isg:depth_from_P")) << scene;
    }
  }
}

// Every shipped preset (presets/*.toml, discovered) runs on a small isg-synth case, and what
// the output says it did (isg:param:* provenance) is what it holds: the channels of each
// effect that ran, and a composite that differs from the beauty where an effect applies.
TEST(CliSynth, EveryShippedPresetRuns) {
  auto dir = isg::test::temp_dir("synth_presets");
  std::string cmd = std::string(ISG_SYNTH_BINARY) + " dof --out " + q(dir) +
                    " --width 96 --height 54 --no-refs --shadowmap-size 128 --threads 2 >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto in = isg::io::read_exr(dir / "aovs.exr");
  size_t count = 0;
  for (const auto& e : fs::directory_iterator(fs::path(ISG_SOURCE_DIR) / "presets")) {
    if (e.path().extension() != ".toml") continue;
    const std::string name = e.path().stem().string();
    ++count;
    const auto out = dir / ("out_" + name + ".exr");
    auto r = run_isg("run " + q(dir / "aovs.exr") + " --scene " + q(dir / "scene.json") + " -o " +
                     q(out) + " --preset " + name);
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    const auto o = isg::io::read_exr(out);
    EXPECT_EQ(o.attributes.get_string("isg:preset"), name);
    auto param = [&](const std::string& k) { return o.attributes.get_string("isg:param:" + k); };
    EXPECT_EQ(param("shadows.method") != "none", o.find("key.softshadow") != nullptr) << name;
    EXPECT_EQ(param("reflections.method") != "none", o.find("refl.glossy.R") != nullptr) << name;
    EXPECT_EQ(param("dof.method") != "none", o.find("dof.coc") != nullptr) << name;
    double diff = 0;
    const auto& a = o.find("R")->data;
    const auto& b = in.find("R")->data;
    for (size_t i = 0; i < a.size(); ++i) diff += std::abs(double(a[i]) - b[i]);
    const bool any = param("shadows.method") != "none" || param("reflections.method") != "none" ||
                     param("dof.method") != "none";
    EXPECT_EQ(diff > 0, any) << name << " changed the composite by " << diff;
  }
  EXPECT_GE(count, 5u);  // default, preview, film, studio-soft, portrait
}

// Temporal stability on a short moving isg-synth sequence (contact: the sphere rolls 0.1 per
// frame). Flicker is measured against the truth's own change: the RMS over the mask of
// (out_t − out_t−1) − (ref_t − ref_t−1) for key.softshadow, next to the same for the hard
// shadow (doing nothing). And the sampling depends on the pixel only: a frame processed alone is
// bitwise the frame processed in the sequence.
TEST(CliSynth, SequenceFlickersLessThanTheHardShadowAndFramesStandAlone) {
  auto dir = isg::test::temp_dir("synth_sequence");
  const int frames = 4;
  for (int f = 1; f <= frames; ++f) {
    const auto fd = dir / ("f" + std::to_string(f));
    std::string cmd = std::string(ISG_SYNTH_BINARY) + " contact --frame " + std::to_string(f) +
                      " --out " + q(fd) + " --width 128 --height 72 --ref-spp 64 " +
                      "--shadowmap-size 128 --threads 2 >/dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    char name[32];
    std::snprintf(name, sizeof name, "shot.%04d.exr", f);
    fs::copy_file(fd / "aovs.exr", dir / name);
  }
  auto r = run_isg("run " + q(dir / "shot.####.exr") + " --scene " + q(dir / "f1" / "scene.json") +
                   " -o " + q(dir / "out.####.exr") + " --frames 1-" + std::to_string(frames));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_isg("run " + q(dir / "shot.0003.exr") + " --scene " + q(dir / "f1" / "scene.json") +
              " -o " + q(dir / "alone.exr"));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto alone = isg::io::read_exr(dir / "alone.exr");
  const auto seq3 = isg::io::read_exr(dir / "out.0003.exr");
  for (const char* c : {"R", "G", "B", "key.softshadow"})
    EXPECT_EQ(alone.find(c)->data, seq3.find(c)->data) << c;

  double e_isg = 0, e_hard = 0;
  size_t n = 0;
  for (int f = 2; f <= frames; ++f) {
    char a[32], b[32];
    std::snprintf(a, sizeof a, "out.%04d.exr", f - 1);
    std::snprintf(b, sizeof b, "out.%04d.exr", f);
    const auto o0 = isg::io::read_exr(dir / a), o1 = isg::io::read_exr(dir / b);
    const auto r0 = isg::io::read_exr(dir / ("f" + std::to_string(f - 1)) / "ref" / "softshadow_key.exr");
    const auto r1 = isg::io::read_exr(dir / ("f" + std::to_string(f)) / "ref" / "softshadow_key.exr");
    const auto &m0 = r0.find("mask")->data, &m1 = r1.find("mask")->data;
    const auto &s0 = o0.find("key.softshadow")->data, &s1 = o1.find("key.softshadow")->data;
    const auto &h0 = o0.find("key.shadow")->data, &h1 = o1.find("key.shadow")->data;
    const auto &t0 = r0.find("key.softshadow")->data, &t1 = r1.find("key.softshadow")->data;
    for (size_t i = 0; i < m0.size(); ++i) {
      if (m0[i] < 0.5f || m1[i] < 0.5f) continue;
      const double dt = double(t1[i]) - t0[i];
      e_isg += std::pow(double(s1[i]) - s0[i] - dt, 2);
      e_hard += std::pow(double(h1[i]) - h0[i] - dt, 2);
      ++n;
    }
  }
  e_isg = std::sqrt(e_isg / double(n));
  e_hard = std::sqrt(e_hard / double(n));
  std::printf("frame-to-frame change against the reference's: isg %.5f, hard %.5f (RMS over %zu px)\n",
              e_isg, e_hard, n);
  // Measured 0.0191 vs 0.0332 (128 x 72, 4 frames, reference 64 spp whose own noise is in it).
  EXPECT_LT(e_isg, 0.025);
  EXPECT_LT(e_isg, 0.7 * e_hard);
}

// Issue 54: a renderer's beauty in one part and AOVs cropped to their bounding box in another
// run as the same channels in one part, with the cropped ones 0 outside their box.
TEST_F(Cli, PartsWithDifferentDataWindowsRunAsOnePart) {
  const int W = 24, H = 16, cx = 4, cy = 2, cw = 16, ch = 12;
  auto img = isg::test::contract_aovs(W, H);
  std::vector<std::string> whole, cropped;
  for (const auto& c : img.channels) (c.name.rfind("key.", 0) == 0 ? cropped : whole).push_back(c.name);
  ASSERT_EQ(cropped.size(), 5u);
  // The one-part reference: the cropped channels 0 outside their box.
  auto one = img;
  for (const auto& n : cropped) {
    auto& d = one.find(n)->data;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (x < cx || x >= cx + cw || y < cy || y >= cy + ch) d[size_t(y * W + x)] = 0.0f;
  }
  isg::io::write_exr(dir / "one.exr", one, {});
  // The two-part file, written through OIIO as a renderer's would be.
  OIIO::ImageSpec a(W, H, int(whole.size()), OIIO::TypeDesc::FLOAT), b(cw, ch, int(cropped.size()), OIIO::TypeDesc::FLOAT);
  a.channelnames = whole;
  b.channelnames = cropped;
  a.alpha_channel = 3;
  b.x = cx;
  b.y = cy;
  b.full_width = W;
  b.full_height = H;
  a.attribute("name", "beauty");
  b.attribute("name", "aovs");
  std::vector<float> pa, pb;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      for (const auto& n : whole) pa.push_back(img.find(n)->data[size_t(y * W + x)]);
      if (x >= cx && x < cx + cw && y >= cy && y < cy + ch)
        for (const auto& n : cropped) pb.push_back(img.find(n)->data[size_t(y * W + x)]);
    }
  const auto two = (dir / "two.exr").string();
  auto o = OIIO::ImageOutput::create(two);
  OIIO::ImageSpec specs[2] = {a, b};
  ASSERT_TRUE(o->open(two, 2, specs));
  ASSERT_TRUE(o->write_image(OIIO::TypeDesc::FLOAT, pa.data()));
  ASSERT_TRUE(o->open(two, b, OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(o->write_image(OIIO::TypeDesc::FLOAT, pb.data()));
  ASSERT_TRUE(o->close());
  for (const char* f : {"one", "two"}) {
    auto r = run_isg("run " + q(dir / (std::string(f) + ".exr")) + " --scene " + q(scene) + " -o " +
                     q(dir / (std::string(f) + "-out.exr")));
    ASSERT_EQ(r.code, 0) << f << ": " << r.err;
  }
  auto want = isg::io::read_exr(dir / "one-out.exr"), got = isg::io::read_exr(dir / "two-out.exr");
  ASSERT_EQ(got.width, W);
  ASSERT_EQ(got.height, H);
  ASSERT_EQ(got.channel_names().size(), want.channel_names().size());
  for (const auto& c : want.channels) {
    ASSERT_NE(got.find(c.name), nullptr) << c.name;
    EXPECT_EQ(got.find(c.name)->data, c.data) << c.name;
  }
}

// Issue 53: depth of field with no camera (eq. 15 from Z, dof.focus_distance and
// dof.coc_infinity), the focus view, and a CoC channel the renderer wrote.
TEST_F(Cli, DofWithoutCameraCocChannelAndFocusView) {
  const std::string base = "run " + q(in) + " --scene " + q(scene) +
                           " --set dof.method=layered --set dof.samples=9 --set dof.coc_source=depth";
  // Without the focus distance and c_inf there is no lens: dof does not run, and the focus view,
  // which pictures its CoC, is refused before any work.
  expect_clean_failure(run_isg(base + " -o " + q(out) + " --focus-view " + q(dir / "fv.png")),
                       "--focus-view needs depth of field", out);
  auto r = run_isg(base + " --set dof.focus_distance=2.08 --set dof.coc_infinity=100 -o " + q(out) +
                   " --focus-view " + q(dir / "fv.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  auto img = isg::io::read_exr(out);
  const auto* coc = img.find("dof.coc");
  ASSERT_NE(coc, nullptr);
  const int W = 24;
  for (int y = 0; y < 16; ++y) {
    const double z = 2.0 + 0.01 * y;  // contract_aovs' depth
    EXPECT_NEAR(coc->data[size_t(y * W + 12)], 100.0 * (z - 2.08) / z, 1e-4) << y;
  }
  auto fv = OIIO::ImageInput::open((dir / "fv.png").string());
  ASSERT_TRUE(fv);
  std::vector<unsigned char> px(size_t(W) * 16 * 3);
  ASSERT_TRUE(fv->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
  auto at = [&](int x, int y, int k) { return int(px[size_t(y * W + x) * 3 + size_t(k)]); };
  EXPECT_GT(at(12, 8, 1), std::max(at(12, 8, 0), at(12, 8, 2)));  // in focus (CoC 0): green
  EXPECT_GT(at(12, 0, 2), at(12, 0, 0));                           // CoC -4: nearer, blue
  EXPECT_GT(at(12, 15, 0), at(12, 15, 2));                         // CoC +3.3: farther, orange

  // A CoC channel in the input (role coc, isg's own dof.coc name), times dof.coc_scale; no depth
  // or camera used.
  auto with_coc = isg::test::contract_aovs(24, 16);
  std::vector<float> ramp(with_coc.pixels());
  for (size_t i = 0; i < ramp.size(); ++i) ramp[i] = float(int(i % 24) - 12);
  with_coc.set("dof.coc", ramp);
  isg::io::write_exr(dir / "coc.exr", with_coc, {});
  r = run_isg("run " + q(dir / "coc.exr") + " --set dof.method=layered --set dof.samples=9 "
              "--set dof.coc_source=channel --set dof.coc_scale=0.5 -o " + q(dir / "coc-out.exr"));
  ASSERT_EQ(r.code, 0) << r.err;
  auto got = isg::io::read_exr(dir / "coc-out.exr");
  for (size_t i = 0; i < ramp.size(); ++i) ASSERT_FLOAT_EQ(got.find("dof.coc")->data[i], 0.5f * ramp[i]) << i;
}
