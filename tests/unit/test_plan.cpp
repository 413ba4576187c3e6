#include <gtest/gtest.h>

#include <array>
#include <cstdio>

#include "effects/params.h"
#include "io/image.h"
#include "io/roles.h"
#include "plan/plan.h"

namespace {
isg::io::Roles roles_of(std::vector<std::string> ch) { return isg::io::resolve_roles(ch, {}, "f.exr"); }
}  // namespace

TEST(Plan, RunsOnlyWhatTheInputsAllow) {
  auto p = isg::effects::default_params();
  auto roles = roles_of({"R", "G", "B", "A", "Z", "key.shadow", "key.direct.R", "key.direct.G",
                         "key.direct.B", "rim.shadow"});
  auto plan = isg::plan::make_plan(roles, {}, p, 8, 4);
  EXPECT_TRUE(plan.missing.empty());
  EXPECT_TRUE(plan.instance("shadows[key]"));
  EXPECT_FALSE(plan.instance("shadows[rim]"));  // rim has no direct
  EXPECT_TRUE(plan.resource("key.shadow"));
  EXPECT_FALSE(plan.resource("rim.shadow"));
  bool rim_reported = false;
  for (const auto& e : plan.effects)
    if (e.effect == "shadows[rim]") rim_reported = !e.runs && e.why.find("rim.direct") != std::string::npos;
  EXPECT_TRUE(rim_reported);
  EXPECT_EQ(plan.resource("composite")->bytes, 8u * 4u * 4u * sizeof(float));
}

TEST(Plan, MethodNoneAllocatesNothingForShadows) {
  auto p = isg::effects::default_params();
  p.set_text("shadows.method", "none", "test");
  auto roles = roles_of({"R", "G", "B", "key.shadow", "key.direct.R", "key.direct.G", "key.direct.B"});
  auto plan = isg::plan::make_plan(roles, {}, p, 8, 4);
  EXPECT_FALSE(plan.instance("shadows[key]"));
  EXPECT_FALSE(plan.resource("key.shadow"));
  EXPECT_FALSE(plan.resource("depth"));  // no depth channel: none allocated
  for (const auto& pass : plan.passes) EXPECT_EQ(pass.name.find("shadows"), std::string::npos);
}

TEST(Plan, PointLightsKeepHardShadows) {
  auto p = isg::effects::default_params();
  isg::io::Scene scene;
  isg::io::Light l;
  l.name = "key";
  l.type = isg::io::LightType::point;
  scene.lights.push_back(l);
  auto roles = roles_of({"R", "G", "B", "key.shadow", "key.direct.R", "key.direct.G", "key.direct.B"});
  auto plan = isg::plan::make_plan(roles, scene, p, 8, 4);
  EXPECT_FALSE(plan.instance("shadows[key]"));
}

TEST(Plan, MissingBeautyIsReported) {
  auto plan = isg::plan::make_plan(roles_of({"Z"}), {}, isg::effects::default_params(), 8, 4);
  ASSERT_FALSE(plan.missing.empty());
  EXPECT_NE(plan.missing[0].find("beauty"), std::string::npos);
}

// shadows.method = auto (issue 19): a floor seen from above, lit from overhead, from 6 degrees
// above its horizon, and overhead again 1e5 m from the world origin.
namespace {
struct AutoFloor {
  double ox = 0, oy = 0;                // the scene's offset from the world origin
  std::array<double, 3> light{0, 0, 4};  // relative to the offset
  int w = 64, h = 48;
  bool camera = true;
  isg::io::Image image() const {
    isg::io::Image img;
    img.width = w;
    img.height = h;
    for (const char* c : {"R", "G", "B", "A", "P.X", "P.Y", "P.Z", "key.shadow", "key.direct.R",
                          "key.direct.G", "key.direct.B", "key.occluder"})
      img.channels.push_back({c, isg::io::Storage::f32, std::vector<float>(size_t(w) * h, 1.0f)});
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        img.find("P.X")->data[i] = float(ox + 0.05 * x - 1.6);
        img.find("P.Y")->data[i] = float(oy + 1.2 - 0.05 * y);
        img.find("P.Z")->data[i] = 0.0f;
      }
    return img;
  }
  isg::io::Scene scene() const {
    isg::io::Scene s;
    isg::io::Camera cam;
    cam.world_to_camera = isg::io::identity4();
    cam.world_to_camera[3] = -ox;
    cam.world_to_camera[7] = -(oy - 1.0);
    cam.world_to_camera[11] = -5.0;  // above the floor, looking down
    cam.yfov_deg = 40.0;
    cam.width = w;
    cam.height = h;
    if (camera) s.camera = cam;
    isg::io::Light l;
    l.name = "key";
    l.type = isg::io::LightType::sphere;
    l.radius = 0.3;
    l.position = {ox + light[0], oy + light[1], light[2]};
    isg::io::ShadowMap sm;
    sm.file = "shadowmap_key.exr";
    sm.yfov_deg = 90.0;
    sm.width = sm.height = 1024;
    l.shadowmap = sm;
    s.lights.push_back(l);
    return s;
  }
};

isg::effects::EffectStatus auto_status(const AutoFloor& f, const char* method = "auto") {
  auto p = isg::effects::default_params();
  p.set_text("shadows.method", method, "test");
  const auto img = f.image();
  const auto scene = f.scene();
  const auto roles = roles_of(img.channel_names());
  const auto choices = isg::plan::choose_from_pixels(roles, scene, p, img, nullptr);
  const auto plan = isg::plan::make_plan(roles, scene, p, f.w, f.h, nullptr, {}, &choices);
  for (const auto& e : plan.effects)
    if (e.effect == "shadows[key]") return e;
  return {};
}
}  // namespace

TEST(Plan, AutoShadowMethodPicksPcssOrIsgFromThePixels) {
  AutoFloor overhead;
  auto st = auto_status(overhead);
  std::printf("overhead: %s (%s)\n", st.method.c_str(), st.why.c_str());
  EXPECT_TRUE(st.runs);
  EXPECT_EQ(st.method, "pcss");
  EXPECT_NE(st.why.find("auto: the light stands"), std::string::npos);

  AutoFloor grazing;
  grazing.light = {-10.0, 0.0, 1.0};  // 5.7 degrees above the floor's middle
  st = auto_status(grazing);
  std::printf("grazing: %s (%s)\n", st.method.c_str(), st.why.c_str());
  EXPECT_EQ(st.method, "isg");
  EXPECT_NE(st.why.find("grazes"), std::string::npos);
  // A shadow-map method named there runs as asked, with a note.
  for (const char* m : {"pcss", "vssm", "cssm"}) {
    st = auto_status(grazing, m);
    std::printf("grazing, %s named: %s (%s)\n", m, st.method.c_str(), st.why.c_str());
    EXPECT_TRUE(st.runs);
    EXPECT_EQ(st.method, m);
    EXPECT_EQ(st.why.rfind("note: shadows.method=auto would take isg here: the light grazes", 0), 0u) << m;
  }
  // Overhead: pcss and vssm named run without a note (vssm's error is the lower, its cost the
  // higher); cssm named, with one for pcss.
  for (const char* m : {"pcss", "vssm"}) EXPECT_EQ(auto_status(overhead, m).why, "") << m;
  st = auto_status(overhead, "cssm");
  std::printf("overhead, cssm named: %s (%s)\n", st.method.c_str(), st.why.c_str());
  EXPECT_TRUE(st.runs);
  EXPECT_EQ(st.method, "cssm");
  EXPECT_EQ(st.why.rfind("note: shadows.method=auto would take pcss here: the light stands", 0), 0u);

  // Far from the origin: isg once float32 positions step by more than a map texel there, pcss
  // under it.
  AutoFloor far;
  far.ox = far.oy = 1e6;
  st = auto_status(far);
  std::printf("far: %s (%s)\n", st.method.c_str(), st.why.c_str());
  EXPECT_EQ(st.method, "isg");
  EXPECT_NE(st.why.find("world origin"), std::string::npos);
  far.ox = far.oy = 1e4;
  st = auto_status(far);
  std::printf("1e4 from the origin: %s (%s)\n", st.method.c_str(), st.why.c_str());
  EXPECT_EQ(st.method, "pcss");

  // Without a camera isg cannot run (its radii are in pixels); pcss with P can.
  AutoFloor no_camera;
  no_camera.camera = false;
  st = auto_status(no_camera);
  EXPECT_EQ(st.method, "pcss");
  EXPECT_NE(st.why.find("no camera"), std::string::npos);

  // Before the pixels are read (a dry run): isg, and the status says the choice is pending.
  auto p = isg::effects::default_params();
  p.set_text("shadows.method", "auto", "test");
  const auto img = overhead.image();
  const auto plan = isg::plan::make_plan(roles_of(img.channel_names()), overhead.scene(), p, 64, 48);
  ASSERT_TRUE(plan.instance("shadows[key]"));
  for (const auto& e : plan.effects)
    if (e.effect == "shadows[key]") {
      EXPECT_EQ(e.why, "auto: isg or pcss, chosen when the pixels are read");
    }
}
