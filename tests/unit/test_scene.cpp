#include <gtest/gtest.h>

#include <cmath>

#include "io/scene.h"
#include "support/images.h"

using isg::io::IoError;

namespace {
const char* kScene = R"({
  "units": "m", "scene_radius": 6.0,
  "camera": {"world_to_camera": [1,0,0,0, 0,1,0,0, 0,0,1,-5, 0,0,0,1], "projection": "perspective",
             "yfov_deg": 40.0, "width": 64, "height": 32, "near": 0.1, "far": 100.0,
             "focus_distance": 5.0, "fstop": 2.8, "focal_length_mm": 50, "sensor_width_mm": 36},
  "lights": [{"name": "key", "type": "sphere", "position": [1, 2, 3], "radius": 0.3,
              "shadowmap": {"file": "shadowmap_key.exr",
                            "world_to_light": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
                            "projection": "perspective", "yfov_deg": 90.0, "near": 0.05,
                            "far": 50.0, "width": 1024, "height": 1024}},
             {"name": "fill", "type": "rect", "position": [0, 0, 4], "normal": [0, 0, -2],
              "size": [1, 2], "u_axis": [1, 0, 0]}]
})";

// `s` with its first `from` replaced by `to`.
std::string replaced(std::string s, const std::string& from, const std::string& to) {
  auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}
std::string with(const std::string& from, const std::string& to) { return replaced(kScene, from, to); }

void expect_error(const std::string& text, const std::string& needle) {
  try {
    isg::io::parse_scene(text, "scene.json");
    FAIL() << "accepted; expected an error about " << needle;
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(Scene, ParsesTheContractExample) {
  auto s = isg::io::parse_scene(kScene, "/x/scene.json");
  ASSERT_TRUE(s.camera);
  EXPECT_EQ(s.camera->width, 64);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, isg::io::LightType::sphere);
  ASSERT_TRUE(s.lights[0].shadowmap);
  EXPECT_EQ(s.lights[0].shadowmap->file, std::filesystem::path("/x/shadowmap_key.exr"));
  EXPECT_NEAR(s.lights[1].normal[2], -1.0, 1e-12);  // normalised
}

TEST(Scene, BadValuesNameTheKey) {
  expect_error(with("\"scene_radius\": 6.0", "\"scene_radius\": -1"), "scene_radius");
  expect_error(with("\"yfov_deg\": 40.0", "\"yfov_deg\": 400"), "camera.yfov_deg");
  expect_error(with("\"radius\": 0.3", "\"radius\": 0.3, \"colour\": 1"), "lights[0].colour: unknown key");
  expect_error(with("\"type\": \"sphere\"", "\"type\": \"cone\""), "lights[0].type");
  expect_error(with("\"width\": 64", "\"width\": 64.5"), "camera.width");
  expect_error(with("[1,0,0,0, 0,1,0,0, 0,0,1,-5, 0,0,0,1]", "[0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,0]"),
               "camera.world_to_camera");
  expect_error(with("\"name\": \"fill\"", "\"name\": \"key\""), "duplicate light name");
  expect_error("{\"scene_radius\": 1", "not valid JSON");
  expect_error("{\"scene_radius\": 1e999}", "not valid JSON");  // found by fuzz_scene
  expect_error(with("\"size\": [1, 2]", "\"size\": [1, 0]"), "lights[1].size");
}

TEST(Scene, ProjectionMatchesPinholeGeometry) {
  auto s = isg::io::parse_scene(kScene, "scene.json");
  const auto& c = *s.camera;
  // The camera sits at z = 5 looking down -Z: the origin projects to the image centre.
  auto p = c.project({0, 0, 0});
  EXPECT_NEAR(p[0], 32.0, 1e-9);
  EXPECT_NEAR(p[1], 16.0, 1e-9);
  EXPECT_NEAR(p[2], 5.0, 1e-12);
  // A point at the top edge of the frustum lands on row 0.
  double t = std::tan(20.0 * M_PI / 180.0);
  EXPECT_NEAR(c.project({0, 5.0 * t, 0})[1], 0.0, 1e-9);
  EXPECT_NEAR(c.pixel_size_at(5.0), 2 * 5.0 * t / 32.0, 1e-12);
}

TEST(Scene, CameraRoundTripsThroughTheExrHeader) {
  auto s = isg::io::parse_scene(kScene, "scene.json");
  isg::io::Image img = isg::test::make_image(64, 32, {"R"}, [](auto&, int, int) { return 0.f; });
  isg::io::set_camera_attributes(img, *s.camera);
  auto dir = isg::test::temp_dir("cam");
  isg::io::write_exr(dir / "c.exr", img, {});
  auto back = isg::io::camera_from_header(isg::io::read_exr(dir / "c.exr"));
  ASSERT_TRUE(back);
  EXPECT_NEAR(back->yfov_deg, 40.0, 1e-4);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(back->world_to_camera[i], s.camera->world_to_camera[i], 1e-6);
  auto p = back->project({0.3, -0.2, 0.1});
  auto q = s.camera->project({0.3, -0.2, 0.1});
  EXPECT_NEAR(p[0], q[0], 1e-3);
  EXPECT_NEAR(p[1], q[1], 1e-3);
}

TEST(Scene, InverseIsExactOnFarFromOriginTransforms) {
  isg::io::Mat4 m = {0.6, 0.8, 0, 1e5, -0.8, 0.6, 0, -2e5, 0, 0, 1, 3e5, 0, 0, 0, 1};
  auto id = isg::io::mul(m, isg::io::inverse(m));
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(id[i], isg::io::identity4()[i], 1e-9);
}

// Issue 52: the contract's spot and sun, and an orthographic map; bad specs name their key.
namespace {
const char* kSun = R"({"name": "sun", "type": "sun", "direction": [0, 3, 4], "angle_deg": 2.0,
  "shadowmap": {"file": "shadowmap_sun.exr", "world_to_light": [1,0,0,0, 0,0.8,-0.6,0, 0,0.6,0.8,-50, 0,0,0,1],
                "projection": "orthographic", "width_m": 40.0, "height_m": 30.0,
                "near": 0.0, "far": 200.0, "width": 2048, "height": 1536}})";
const char* kSpot = R"({"name": "spot", "type": "spot", "position": [0, 0, 5], "radius": 0.25,
  "normal": [0, 0, -1], "spot_angle_deg": 60, "spot_blend": 0.3})";
std::string scene_with_lights(const std::string& lights) {
  return std::string(R"({"scene_radius": 6.0, "lights": [)") + lights + "]}";
}
// kSun (or kSpot) with one replacement.
std::string light_with(const char* light, const std::string& from, const std::string& to) {
  return scene_with_lights(replaced(light, from, to));
}
}  // namespace

TEST(Scene, ReadsSunAndSpotWithAnOrthographicMap) {
  auto s = isg::io::parse_scene(scene_with_lights(std::string(kSun) + "," + kSpot), "/x/scene.json");
  ASSERT_EQ(s.lights.size(), 2u);
  const auto& sun = s.lights[0];
  EXPECT_EQ(sun.type, isg::io::LightType::sun);
  EXPECT_TRUE(sun.distant());
  EXPECT_NEAR(sun.direction[1], 0.6, 1e-12);  // normalised
  EXPECT_NEAR(sun.direction[2], 0.8, 1e-12);
  EXPECT_EQ(sun.angle_deg, 2.0);
  ASSERT_TRUE(sun.shadowmap);
  EXPECT_TRUE(sun.shadowmap->orthographic());
  EXPECT_EQ(sun.shadowmap->width_m, 40.0);
  EXPECT_EQ(sun.shadowmap->height_m, 30.0);
  EXPECT_EQ(sun.shadowmap->near_clip, 0.0);
  EXPECT_EQ(sun.shadowmap->far_clip, 200.0);
  const auto& spot = s.lights[1];
  EXPECT_EQ(spot.type, isg::io::LightType::spot);
  EXPECT_FALSE(spot.distant());
  EXPECT_EQ(spot.radius, 0.25);
  EXPECT_EQ(spot.spot_angle_deg, 60.0);
  EXPECT_EQ(spot.spot_blend, 0.3);
  EXPECT_STREQ(isg::io::to_string(spot.type), "spot");
  EXPECT_STREQ(isg::io::to_string(sun.type), "sun");
}

TEST(Scene, BadSunAndSpotSpecsNameTheKey) {
  // A sun with a position but no direction; angles out of (0, 90); a map without its extent.
  expect_error(light_with(kSun, "\"direction\": [0, 3, 4]", "\"position\": [0, 3, 4]"), "lights[0].position");
  expect_error(light_with(kSun, "\"direction\": [0, 3, 4], ", ""), "lights[0].direction: missing");
  expect_error(light_with(kSun, "\"angle_deg\": 2.0", "\"angle_deg\": 0"), "lights[0].angle_deg");
  expect_error(light_with(kSun, "\"angle_deg\": 2.0", "\"angle_deg\": -1"), "lights[0].angle_deg");
  expect_error(light_with(kSun, "\"angle_deg\": 2.0", "\"angle_deg\": 90"), "lights[0].angle_deg");
  expect_error(light_with(kSun, "\"width_m\": 40.0, ", ""), "lights[0].shadowmap.width_m: missing");
  expect_error(light_with(kSun, "\"height_m\": 30.0", "\"height_m\": 0"), "lights[0].shadowmap.height_m");
  expect_error(light_with(kSun, "\"orthographic\"", "\"perspective\", \"yfov_deg\": 60"),
               "lights[0].shadowmap.projection");
  expect_error(light_with(kSun, "\"angle_deg\": 2.0", "\"angle_deg\": 2.0, \"radius\": 1"), "lights[0].radius");
  expect_error(light_with(kSun, "\"far\": 200.0", "\"far\": -1"), "lights[0].shadowmap.far");
  expect_error(light_with(kSun, "\"near\": 0.0", "\"near\": -5"), "lights[0].shadowmap.near");
  expect_error(light_with(kSun, "\"height_m\": 30.0", "\"height_m\": 40.0"), "lights[0].shadowmap.height_m");
  expect_error(light_with(kSun, "\"direction\": [0, 3, 4]", "\"direction\": [0, 4, 3]"), "lights[0].shadowmap.world_to_light");
  // A spot: a cone in (0, 180], a blend in [0, 1], its axis; a sun's keys are not its own.
  expect_error(light_with(kSpot, "\"spot_angle_deg\": 60", "\"spot_angle_deg\": 0"), "lights[0].spot_angle_deg");
  expect_error(light_with(kSpot, "\"spot_blend\": 0.3", "\"spot_blend\": 1.5"), "lights[0].spot_blend");
  expect_error(light_with(kSpot, "\"normal\": [0, 0, -1], ", ""), "lights[0].normal: missing");
  expect_error(light_with(kSpot, "\"radius\": 0.25", "\"radius\": 0.25, \"angle_deg\": 1"), "lights[0].angle_deg");
  // An orthographic map belongs to a sun only; spot keys to a spot only.
  expect_error(with("\"projection\": \"perspective\", \"yfov_deg\": 90.0",
                    "\"projection\": \"orthographic\", \"width_m\": 4, \"height_m\": 4"),
               "lights[0].shadowmap.projection");
  expect_error(with("\"radius\": 0.3", "\"radius\": 0.3, \"spot_blend\": 0.2"), "lights[0].spot_blend");
}
