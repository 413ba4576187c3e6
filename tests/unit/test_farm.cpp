// lib/farm without Slurm: chunks and their --frames spellings against parse_frames (the syntax
// `isg run` reads), the sbatch script run by bash as Slurm would run one array task, and the
// summary read back from result files, logs and outputs made here. The one-node cluster test
// (tests/farm/slurm_cluster.py) runs the real thing.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "farm/farm.h"
#include "frames/frames.h"
#include "run/job.h"
#include "support/images.h"

namespace fs = std::filesystem;
using namespace isg;

namespace {

std::string slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

}  // namespace

TEST(FarmChunks, SpecsSpellExactlyTheirFrames) {
  EXPECT_EQ(farm::frames_spec({1001, 1002, 1003}), "1001-1003");
  EXPECT_EQ(farm::frames_spec({1001, 1005, 1009, 1013}), "1001-1013x4");
  EXPECT_EQ(farm::frames_spec({1, 3}), "1,3");
  EXPECT_EQ(farm::frames_spec({7}), "7");
  EXPECT_EQ(farm::frames_spec({1, 2, 3, 10, 20, 30, 31}), "1-3,10-30x10,31");
  // Any ascending list: the spec reads back as the same frames.
  std::mt19937 rng(21);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<int> frames;
    int f = int(rng() % 2000) - 100;
    for (int n = int(rng() % 40) + 1; n > 0; --n) {
      frames.push_back(f);
      f += rng() % 3 == 0 ? int(rng() % 7) + 1 : 1;
    }
    EXPECT_EQ(isg::frames::parse_frames(farm::frames_spec(frames)), frames) << farm::frames_spec(frames);
  }
}

TEST(FarmChunks, CoverTheRangeInOrderWithTaskIdsFromZero) {
  const auto frames = isg::frames::parse_frames("1001-1100");
  const auto chunks = farm::make_chunks(frames, 7);
  ASSERT_EQ(chunks.size(), 15u);  // 14 of 7 and one of 2
  std::vector<int> all;
  for (size_t i = 0; i < chunks.size(); ++i) {
    EXPECT_EQ(chunks[i].task, int(i));
    EXPECT_LE(chunks[i].frames.size(), 7u);
    EXPECT_EQ(isg::frames::parse_frames(chunks[i].spec), chunks[i].frames);
    all.insert(all.end(), chunks[i].frames.begin(), chunks[i].frames.end());
  }
  EXPECT_EQ(all, frames);
  EXPECT_EQ(chunks.back().spec, "1099-1100");
  EXPECT_THROW(farm::make_chunks(frames, 0), farm::UsageError);
}

TEST(FarmScript, EachArrayTaskRunsItsChunkAndLeavesAResult) {
  const auto dir = test::temp_dir("farm_script");
  // A stand-in for isg that records its arguments and exits 3 (some frames failed).
  const fs::path fake = dir / "fake isg";
  write(fake,
        "#!/bin/bash\nprintf '%s\\n' \"$@\" > \"$(dirname "
        "\"$0\")/args.$SLURM_ARRAY_TASK_ID\"\nexit 3\n");
  fs::permissions(fake, fs::perms::owner_all);
  farm::JobSpec job;
  job.input = "/in/shot.####.exr";
  job.output = "/out/it's.####.exr";
  job.frames = isg::frames::parse_frames("1001-1100");
  job.chunk = 10;
  job.max_parallel = 4;
  job.isg = fake.string();
  job.run_args = {"--scene", "/s/scene file.json", "--set", "shadows.method=hard"};
  job.skip_existing = true;
  job.log_dir = dir / "logs";
  job.workdir = dir;
  job.sbatch_args = {"--time=10"};
  const auto chunks = farm::make_chunks(job.frames, job.chunk);
  const std::string script = farm::sbatch_script(job, chunks);
  EXPECT_NE(script.find("#SBATCH --array=0-9%4\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --output=" + job.log_dir.string() + "/%A.%a.log\n"),
            std::string::npos);
  EXPECT_NE(script.find("#SBATCH --time=10\n"), std::string::npos);
  // Every #SBATCH line before the first command (sbatch stops reading them there).
  EXPECT_LT(script.rfind("#SBATCH"), script.find("frames=("));
  fs::create_directories(job.log_dir);
  write(dir / "job.sbatch", script);
  for (int task : {0, 3, 9}) {
    const std::string cmd = "cd '" + dir.string() +
                            "' && SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
                            " SLURM_ARRAY_JOB_ID=77 bash job.sbatch > task.out 2>&1";
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc));
    EXPECT_EQ(WEXITSTATUS(rc), 3) << slurp(dir / "task.out");  // the task exits as isg did
    std::istringstream args(slurp(dir / ("args." + std::to_string(task))));
    std::vector<std::string> argv;
    for (std::string a; std::getline(args, a);) argv.push_back(a);
    const int first = 1001 + 10 * task;
    const std::vector<std::string> want{
        "run",          job.input,
        "-o",           job.output,
        "--frames",     std::to_string(first) + "-" + std::to_string(first + 9),
        "--keep-going", "--skip-existing",
        "--scene",      "/s/scene file.json",
        "--set",        "shadows.method=hard"};
    EXPECT_EQ(argv, want);
    EXPECT_EQ(slurp(farm::task_result(job.log_dir, "77", task)), "3 " + want[5] + "\n");
  }
  // By hand (no array id) the script refuses to run.
  EXPECT_NE(std::system(("cd '" + dir.string() + "' && bash job.sbatch >/dev/null 2>&1").c_str()),
            0);
  job.log_dir = dir / "with space";
  EXPECT_THROW(farm::sbatch_script(job, chunks), farm::UsageError);
}

TEST(FarmSummary, FailedFramesAreThoseWithoutOutputWithTheLogsReason) {
  const auto dir = test::temp_dir("farm_summary");
  const fs::path logs = dir / "logs";
  fs::create_directories(logs);
  farm::Manifest m{"12", (dir / "in.####.exr").string(), (dir / "out.####.exr").string(),
                   farm::make_chunks(isg::frames::parse_frames("1001-1010"), 4)};
  farm::write_manifest(logs, m);
  for (int f : {1001, 1002, 1003, 1004, 1006, 1008}) write(isg::frames::expand_pattern(m.output, f), "exr");
  // Task 0: all written. Task 1: frame 1005 bad, 1007 failed after its log line was cut.
  // Task 2 (1009-1010): never ran, no log, no result.
  write(farm::task_result(logs, "12", 0), "0 1001-1004\n");
  write(farm::task_log(logs, "12", 0),
        "frame 1001: wrote x (1/4 frames)\nframes: 4 written, 0 skipped (existing), 0 failed, in 1 "
        "s\n");
  write(farm::task_result(logs, "12", 1), "3 1005-1008\n");
  write(farm::task_log(logs, "12", 1),
        "isg: error: frame 1005: /in.1005.exr: truncated\nframes: 2 written, 0 skipped (existing), "
        "2 failed\n");
  const auto s = farm::summarize(logs);
  EXPECT_EQ(s.frames, 10u);
  EXPECT_EQ(s.written, 6u);
  ASSERT_EQ(s.failed.size(), 4u);
  EXPECT_EQ(s.failed[0].frame, 1005);
  EXPECT_EQ(s.failed[0].message, "/in.1005.exr: truncated");
  EXPECT_EQ(s.failed[1].frame, 1007);
  EXPECT_NE(s.failed[1].message.find("no output"), std::string::npos);
  EXPECT_EQ(s.failed[2].frame, 1009);
  EXPECT_NE(s.failed[2].message.find("left no result"), std::string::npos);
  EXPECT_EQ(s.exit_code(), farm::kError);  // a task that never reported is not a frame failure
  EXPECT_NE(farm::describe(s).find("failed frames: 1005,1007,1009,1010\n"), std::string::npos)
      << farm::describe(s);
  // Once task 2 reports, only frames failed: exit 3 (retry them).
  write(farm::task_result(logs, "12", 2), "3 1009-1010\n");
  EXPECT_EQ(farm::summarize(logs).exit_code(), farm::kSomeFramesFailed);
  for (int f : {1005, 1007, 1009, 1010}) write(isg::frames::expand_pattern(m.output, f), "exr");
  EXPECT_EQ(farm::summarize(logs).exit_code(), farm::kOk);
  write(farm::task_result(logs, "12", 2), "2 1009-1010\n");
  EXPECT_EQ(farm::summarize(logs).exit_code(), farm::kUsage);
  EXPECT_THROW(farm::summarize(dir), farm::FarmError);  // no manifest
}
