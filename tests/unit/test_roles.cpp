#include <gtest/gtest.h>

#include "io/image.h"
#include "io/roles.h"

using isg::io::resolve_roles;

TEST(Roles, ContractNames) {
  std::vector<std::string> ch = {"R", "G", "B", "A", "Z", "P.X", "P.Y", "P.Z", "N.X", "N.Y",
                                 "N.Z", "key.shadow", "key.occluder", "key.direct.R",
                                 "key.direct.G", "key.direct.B", "refl.R", "refl.G", "refl.B"};
  auto r = resolve_roles(ch, {}, "f.exr");
  EXPECT_TRUE(r.has("beauty"));
  EXPECT_TRUE(r.has("depth"));
  EXPECT_TRUE(r.has("position"));
  EXPECT_TRUE(r.has("normal"));
  EXPECT_TRUE(r.has("refl"));
  EXPECT_FALSE(r.has("refl.weight"));
  ASSERT_EQ(r.lights, std::vector<std::string>{"key"});  // discovered without a scene file
  EXPECT_TRUE(r.has("key.shadow"));
  EXPECT_TRUE(r.has("key.direct"));
  EXPECT_EQ(r.get("key.direct")->components(), 3u);
}

TEST(Roles, BlenderNamesAnyLayer) {
  std::vector<std::string> ch = {"Shot.Combined.R", "Shot.Combined.G", "Shot.Combined.B",
                                 "Shot.Combined.A", "Shot.Depth.Z", "Shot.Position.X",
                                 "Shot.Position.Y", "Shot.Position.Z", "Shot.GlossDir.R",
                                 "Shot.GlossDir.G", "Shot.GlossDir.B", "Shot.GlossInd.R",
                                 "Shot.GlossInd.G", "Shot.GlossInd.B"};
  auto r = resolve_roles(ch, {}, "f.exr");
  EXPECT_EQ(r.layer, "Shot");
  EXPECT_EQ(r.get("depth")->terms.front().front(), "Shot.Depth.Z");
  ASSERT_TRUE(r.has("refl"));
  EXPECT_EQ(r.get("refl")->terms.size(), 2u);  // GlossDir + GlossInd
  EXPECT_FALSE(r.has("normal"));
}

TEST(Roles, SeveralLayersNeedALayerChoice) {
  std::vector<std::string> ch = {"A.Depth.Z", "B.Depth.Z"};
  try {
    resolve_roles(ch, {}, "two.exr");
    FAIL();
  } catch (const isg::io::IoError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("two.exr"), std::string::npos);
    EXPECT_NE(m.find("A, B"), std::string::npos) << m;
  }
  isg::io::RoleRequest req;
  req.layer = "B";
  EXPECT_EQ(resolve_roles(ch, req, "two.exr").get("depth")->terms[0][0], "B.Depth.Z");
  req.layer = "C";
  EXPECT_THROW(resolve_roles(ch, req, "two.exr"), isg::io::IoError);
}

TEST(Roles, OverridesByPrefixListOrName) {
  std::vector<std::string> ch = {"rgba.R", "rgba.G", "rgba.B", "depth", "Nw.X", "Nw.Y", "Nw.Z",
                                 "x", "y", "z"};
  isg::io::RoleRequest req;
  req.overrides = {{"beauty", "rgba"}, {"depth", "depth"}, {"normal", "Nw"}, {"position", "x,y,z"}};
  auto r = resolve_roles(ch, req, "f.exr");
  EXPECT_EQ(r.get("beauty")->components(), 3u);  // alpha optional
  EXPECT_EQ(r.get("normal")->terms[0][2], "Nw.Z");
  EXPECT_EQ(r.get("position")->terms[0][1], "y");
  EXPECT_EQ(r.get("depth")->how, "--channel");
  req.overrides = {{"depth", "nope"}};
  try {
    resolve_roles(ch, req, "f.exr");
    FAIL();
  } catch (const isg::io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("no channel nope"), std::string::npos) << e.what();
  }
}

TEST(Roles, GatherSumsTermsAndFillsAlpha) {
  isg::io::Image img;
  img.width = 2;
  img.height = 1;
  img.channels = {{"a.R", isg::io::Storage::f32, {1, 2}}, {"a.G", isg::io::Storage::f32, {3, 4}},
                  {"a.B", isg::io::Storage::f32, {5, 6}}, {"b.R", isg::io::Storage::f32, {10, 20}},
                  {"b.G", isg::io::Storage::f32, {30, 40}}, {"b.B", isg::io::Storage::f32, {50, 60}}};
  isg::io::RoleBinding b{"refl", {{"a.R", "a.G", "a.B"}, {"b.R", "b.G", "b.B"}}, "test"};
  auto v = isg::io::gather_role(img, b, 4, 1.0f);
  std::vector<float> want = {11, 22, 33, 44, 55, 66, 1, 1};
  EXPECT_EQ(v, want);
}
