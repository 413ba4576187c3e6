// `isg farm` end to end without Slurm: the script --dry-run prints, the checks made before
// anything is submitted (exit 2 for a bad command line, 1 for bad input), `isg farm status`.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <fstream>
#include <sstream>

#include "support/command.h"
#include "support/images.h"

namespace fs = std::filesystem;

namespace {

using Result = isg::test::CommandResult;

Result isg_cli(const std::string& args) {
  return isg::test::run_command(std::string(ISG_BINARY) + " " + args);
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

class Farm : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = isg::test::temp_dir(std::string("farm_") +
                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir / "comp");
    std::ofstream(dir / "scene.json")
        << R"({"scene_radius": 3.0, "lights": [{"name": "key", "type": "sphere",
      "position": [0, 0, 5], "radius": 0.2}]})";
    base = "farm submit " + q(dir / "shot.####.exr") + " -o " + q(dir / "comp" / "shot.####.exr") +
           " --scene " + q(dir / "scene.json");
  }
  fs::path dir;
  std::string base;
};

}  // namespace

TEST_F(Farm, DryRunPrintsTheArrayScriptWithTaskIdsFromZero) {
  auto r = isg_cli(base +
                   " --frames 1001-1100 --chunk 10 --max-parallel 3 --preset film --set "
                   "shadows.method=hard --dry-run");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("#SBATCH --array=0-9%3\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("#SBATCH --output=" + (dir / "comp" / "isg-farm").string() + "/%A.%a.log"),
            std::string::npos)
      << r.out;
  for (int t = 0; t < 10; ++t) {
    const std::string row =
        "  " + std::to_string(1001 + 10 * t) + "-" + std::to_string(1010 + 10 * t) + "\n";
    EXPECT_NE(r.out.find(row), std::string::npos) << row;
  }
  EXPECT_NE(r.out.find("--frames \"$spec\" --keep-going '--preset' 'film' '--set' "
                       "'shadows.method=hard' '--scene' " +
                       q(dir / "scene.json")),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(dir / "comp" / "isg-farm")) << "a dry run writes nothing";
  // --skip-existing leaves out frames whose output exists: 1001-1003 and 1050 here.
  for (int f : {1001, 1002, 1003, 1050})
    std::ofstream(dir / "comp" / ("shot." + std::to_string(f) + ".exr")) << "x";
  r = isg_cli(base + " --frames 1001-1100 --chunk 48 --skip-existing --dry-run");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("#SBATCH --array=0-1\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  1004-1049,1051-1052\n  1053-1100\n)"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("4 of 100 outputs exist, skipped"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("--keep-going --skip-existing"), std::string::npos);
}

TEST_F(Farm, BadCommandLinesExit2AndBadInputExit1BeforeAnythingIsSubmitted) {
  struct Case {
    std::string args, needle;
    int code;
  };
  const std::vector<Case> cases = {
      {base + " --frames 7-3 --dry-run", "--frames 7-3", 2},
      {base + " --frames 1-9 --set shadows.nope=1 --dry-run", "shadows.nope", 2},
      {base + " --frames 1-9 --set shadows.method=bogus --dry-run", "shadows.method", 2},
      {base + " --frames 1-9 --preset no-such-look --dry-run", "no-such-look", 2},
      {base + " --frames 1-9 --chunk 0 --dry-run", "--chunk", 2},
      {base + " --frames 1-9 --max-parallel=-1 --dry-run", "--max-parallel", 2},
      {base + " --frames 1-9 --dry-run --log-dir " + q(dir / "with space"), "with space", 2},
      {"farm submit " + q(dir / "shot.exr") + " -o " + q(dir / "o.####.exr") +
           " --frames 1-2 --dry-run",
       "shot.exr", 2},
      {"farm submit " + q(dir / "shot.####.exr") + " -o " + q(dir / "none" / "o.####.exr") +
           " --frames 1-2 --dry-run",
       (dir / "none").string(), 1},
      {"farm submit " + q(dir / "shot.####.exr") + " -o " + q(dir / "o.####.exr") +
           " --frames 1-2 --dry-run --scene " + q(dir / "nope.json"),
       "nope.json", 1},
      {"farm status " + q(dir), "isg-farm.json", 1},
      {"farm submit --frames 1-2 --dry-run", "", 2},  // CLI11's own errors exit 2 as well
      {"run --no-such-flag", "", 2},
  };
  for (const auto& c : cases) {
    const auto r = isg_cli(c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.err;
    if (c.needle.empty()) continue;
    EXPECT_NE(r.err.find("isg: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "comp" / "isg-farm"));
}
