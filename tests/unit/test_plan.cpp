#include <gtest/gtest.h>

#include "effects/params.h"
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
