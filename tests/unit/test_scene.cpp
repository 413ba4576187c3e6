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

std::string with(const std::string& from, const std::string& to) {
  std::string s = kScene;
  auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}

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
  expect_error(with("\"type\": \"sphere\"", "\"type\": \"spot\""), "lights[0].type");
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
