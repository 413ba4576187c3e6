#include <gtest/gtest.h>

#include <fstream>

#include "effects/params.h"
#include "support/images.h"

using isg::params::ParamError;

namespace {
std::filesystem::path write(const std::filesystem::path& dir, const std::string& name,
                            const std::string& text) {
  auto p = dir / name;
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(Params, DefaultsComeFromTheTable) {
  auto p = isg::effects::default_params();
  for (const auto& d : p.defs()) {
    if (d.type == isg::params::Type::number) {
      EXPECT_DOUBLE_EQ(p.number(d.key), std::stod(d.def)) << d.key;
    } else {
      EXPECT_EQ(p.text(d.key), d.def) << d.key;
    }
  }
  EXPECT_EQ(p.choice("output.compression"), "zip");
}

TEST(Params, SetValidatesTypeAndRange) {
  auto p = isg::effects::default_params();
  p.set_text("output.compression", "piz", "--set");
  EXPECT_EQ(p.choice("output.compression"), "piz");
  EXPECT_THROW(p.set_text("output.compression", "jpeg", "--set"), ParamError);
  EXPECT_THROW(p.set_text("limits.max_channels", "0", "--set"), ParamError);
  EXPECT_THROW(p.set_text("limits.max_channels", "12x", "--set"), ParamError);
  EXPECT_THROW(p.set_text("no.such", "1", "--set"), ParamError);
  try {
    p.set_text("limits.max_megapixels", "-3", "--set");
    FAIL();
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("limits.max_megapixels"), std::string::npos);
  }
}

TEST(Params, PresetErrorsNameFileAndLine) {
  auto dir = isg::test::temp_dir("params");
  auto f = write(dir, "bad.toml", "description = \"x\"\n\n[output]\ncompression = \"zip\"\nfoo = 3\n");
  auto p = isg::effects::default_params();
  try {
    p.load_preset(f.string(), {dir});
    FAIL() << "unknown key accepted";
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("output.foo"), std::string::npos) << e.what();
  }
  auto g = write(dir, "range.toml", "[limits]\nmax_channels = -1\n");
  try {
    p.load_preset(g.string(), {dir});
    FAIL();
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("range.toml:2"), std::string::npos) << e.what();
  }
  auto h = write(dir, "syntax.toml", "[output\n");
  EXPECT_THROW(p.load_preset(h.string(), {dir}), ParamError);
}

TEST(Params, InheritanceAndChannels) {
  auto dir = isg::test::temp_dir("inherit");
  write(dir, "base1.toml", "[output]\ncompression = \"piz\"\n[limits]\nmax_channels = 50\n");
  auto child = write(dir, "child.toml",
                     "base = \"base1\"\n[limits]\nmax_channels = 60\n[channels]\nnormal = \"Nw\"\n");
  auto p = isg::effects::default_params();
  p.load_preset(child.string(), {dir});
  EXPECT_EQ(p.choice("output.compression"), "piz");  // inherited
  EXPECT_EQ(p.integer("limits.max_channels"), 60);   // overridden
  ASSERT_EQ(p.channels().count("normal"), 1u);
  EXPECT_EQ(p.channels().at("normal").name, "Nw");
  auto loop = write(dir, "loop.toml", "base = \"loop\"\n");
  EXPECT_THROW(p.load_preset(loop.string(), {dir}), ParamError);
}

TEST(Params, PrintPresetRoundTrips) {
  auto p = isg::effects::default_params();
  p.set_text("output.compression", "b44", "--set");
  p.set_text("limits.max_megapixels", "12.5", "--set");
  auto dir = isg::test::temp_dir("roundtrip");
  auto f = write(dir, "printed.toml", p.to_toml());
  auto q = isg::effects::default_params();
  q.load_preset(f.string(), {dir});
  for (const auto& d : p.defs()) EXPECT_EQ(p.text(d.key), q.text(d.key)) << d.key;
}

TEST(Params, ShippedPresetsLoad) {
  std::vector<std::filesystem::path> dirs = {ISG_SOURCE_PRESETS};
  auto list = isg::params::list_presets(dirs);
  ASSERT_FALSE(list.empty());
  for (const auto& info : list) {
    auto p = isg::effects::default_params();
    EXPECT_NO_THROW(p.load_preset(info.name, dirs)) << info.name;
    EXPECT_FALSE(info.description.empty()) << info.name;
  }
}
