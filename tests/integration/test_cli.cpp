// The ultrafusion executable as a user meets it: exit codes (0 ok, 1 data error, 2 usage error), messages
// that name file and line, and the JSON and PNG outputs of `eval`.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

using test::CommandResult;
using test::Ultrafusion;

// A 20 s figure-eight at 10 Hz and an estimate with a known offset and noise-free drift along x.
std::string Figure8(const testing::TempDir& dir, const std::string& name, double drift_per_s) {
  std::string text = "# t x y z qx qy qz qw\n";
  char line[256];
  for (int i = 0; i < 200; ++i) {
    const double t = 0.1 * i;
    std::snprintf(line, sizeof(line), "%.9f %.9f %.9f %.9f 0 0 %.9f %.9f\n", 100 + t,
                  10 * std::sin(0.3 * t) + drift_per_s * t, 5 * std::sin(0.6 * t), 0.1 * t,
                  std::sin(0.05 * t), std::cos(0.05 * t));
    text += line;
  }
  return dir.Write(name, text);
}

TEST(Cli, VersionHelpAndUsageErrors) {
  const CommandResult version = Ultrafusion("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_NE(version.output.find("ultrafusion 0.1.0"), std::string::npos) << version.output;
  EXPECT_EQ(Ultrafusion("eval --help").code, 0);
  EXPECT_EQ(Ultrafusion("").code, 2);  // a subcommand is required
  EXPECT_EQ(Ultrafusion("no-such-command").code, 2);
  EXPECT_EQ(Ultrafusion("eval onlyone.txt").code, 2);  // ESTIMATE missing
  EXPECT_EQ(Ultrafusion("eval a b --align affine").code, 2);
  EXPECT_EQ(Ultrafusion("eval a b --rpe-delta 1.5").code, 2);  // frames must be whole
  EXPECT_EQ(Ultrafusion("eval a b --no-such-option").code, 2);
}

TEST(Cli, EvalWritesFiguresJsonAndPlots) {
  testing::TempDir dir;
  const std::string reference = Figure8(dir, "ref.tum", 0);
  const std::string estimate = Figure8(dir, "est.tum", 0.01);
  const CommandResult run =
      Ultrafusion("eval " + reference + " " + estimate + " --align none --json " + dir.File("e.json") +
                  " --plot " + dir.File("plots") + " --rpe-delta 10");
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("matched:   200 pairs"), std::string::npos) << run.output;
  const auto json = nlohmann::json::parse(testing::ReadText(dir.File("e.json")));
  // Without alignment the error of pose i is exactly the drift 0.01 * 0.1 i: max 0.199, mean 0.0995.
  EXPECT_NEAR(json["ape"]["max"].get<double>(), 0.199, 1e-9);
  EXPECT_NEAR(json["ape"]["mean"].get<double>(), 0.0995, 1e-9);
  EXPECT_EQ(json["ape"]["n"].get<int>(), 200);
  // RPE pairs (0,10), (10,20), ...: each sees 10 frames = 1 s of drift, 0.01 m along world x.
  EXPECT_EQ(json["rpe"]["n"].get<int>(), 19);
  EXPECT_NEAR(json["rpe"]["rmse"].get<double>(), 0.01, 1e-9);
  for (const char* png : {"ape_top_view.png", "ape_over_time.png", "rpe_over_time.png"})
    EXPECT_GT(std::filesystem::file_size(dir.File(std::string("plots/") + png)), 10000u) << png;

  // With se3 alignment, the best translation alone leaves the drift minus its mean, rmse = std of 0.001 i
  // over i = 0..199 = 0.001 sqrt((200^2 - 1) / 12); the rotation of the alignment can only lower it further.
  const CommandResult aligned =
      Ultrafusion("eval " + reference + " " + estimate + " --json " + dir.File("a.json"));
  ASSERT_EQ(aligned.code, 0) << aligned.output;
  const double rmse =
      nlohmann::json::parse(testing::ReadText(dir.File("a.json")))["ape"]["rmse"].get<double>();
  EXPECT_LE(rmse, 0.001 * std::sqrt((200.0 * 200.0 - 1) / 12) + 1e-12);
  EXPECT_GT(rmse, 0.04);  // a curved path: rotation cannot absorb a drift along world x
}

TEST(Cli, DataErrorsNameTheFileAndExitOne) {
  testing::TempDir dir;
  const std::string good = Figure8(dir, "good.tum", 0);
  const std::string bad = dir.Write("bad.tum", "1 0 0 0 0 0 0 1\n2 0 0 oops 0 0 0 1\n");
  CommandResult run = Ultrafusion("eval " + good + " " + bad);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find(bad + ":2: z (column 4) is not a number: 'oops'"), std::string::npos)
      << run.output;

  run = Ultrafusion("eval " + good + " " + dir.File("missing.tum"));
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("missing.tum: cannot open file"), std::string::npos) << run.output;

  // Stamps a minute away from the reference: nothing matches.
  const std::string late = dir.Write("late.tum", "500 0 0 0 0 0 0 1\n501 1 0 0 0 0 0 1\n502 2 1 0 0 0 0 1\n");
  run = Ultrafusion("eval " + good + " " + late);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("too few matched pairs: 0 of 3"), std::string::npos) << run.output;

  // All matched positions on one line: the alignment's rotation is undetermined.
  const std::string line_ref =
      dir.Write("l1.tum", "1 0 0 0 0 0 0 1\n2 1 1 1 0 0 0 1\n3 2 2 2 0 0 0 1\n4 3 3 3 0 0 0 1\n");
  run = Ultrafusion("eval " + line_ref + " " + line_ref);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("degenerate alignment"), std::string::npos) << run.output;
  EXPECT_EQ(Ultrafusion("eval " + line_ref + " " + line_ref + " --align none").code, 0);

  // A stampless KITTI file against a TUM file, and an unwritable JSON path.
  const std::string kitti = dir.Write("k.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
  run = Ultrafusion("eval " + good + " " + kitti);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("--est-times"), std::string::npos) << run.output;
  run = Ultrafusion("eval " + good + " " + good + " --json " + dir.File("no/dir/e.json"));
  EXPECT_EQ(run.code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.File("no/dir/e.json")));
}

// A repeated stamp keeps the first pose, as evo does, and is a counted warning; --strict-stamps makes it an
// error naming file and line. A stamp going backwards is an error either way.
TEST(Cli, RepeatedStampsAreACountedWarningUnlessStrict) {
  testing::TempDir dir;
  const std::string reference = Figure8(dir, "ref.tum", 0);
  const std::string text = testing::ReadText(reference);
  // File line 4 repeats the stamp of line 3 (header, t = 100.0, t = 100.1) with a position 5 m away: kept, it
  // would add a 5 m error.
  const std::size_t line4 = text.find("100.200000000");
  const std::string head = text.substr(0, line4), tail = text.substr(line4);
  const std::string repeated = dir.Write("repeated.tum", head + "100.100000000 5 5 5 0 0 0 1\n" + tail);

  CommandResult run =
      Ultrafusion("eval " + repeated + " " + reference + " --align none --json " + dir.File("e.json"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find(repeated + ": skipped 1 poses repeating the previous stamp"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("(200 poses, 1 repeated stamps skipped)"), std::string::npos) << run.output;
  const auto json = nlohmann::json::parse(testing::ReadText(dir.File("e.json")));
  EXPECT_EQ(json["skipped_duplicate_stamps"]["reference"].get<int>(), 1);
  EXPECT_EQ(json["skipped_duplicate_stamps"]["estimate"].get<int>(), 0);
  EXPECT_EQ(json["reference_poses"].get<int>(), 200);
  EXPECT_NEAR(json["ape"]["max"].get<double>(), 0.0, 1e-9);  // the first pose of the stamp was kept

  run = Ultrafusion("eval " + repeated + " " + reference + " --strict-stamps --json " + dir.File("s.json"));
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find(repeated + ":4: duplicate stamp"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir.File("s.json")));

  const std::string backwards = dir.Write("backwards.tum", head + "50 0 0 0 0 0 0 1\n" + tail);
  run = Ultrafusion("eval " + backwards + " " + reference);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find(backwards + ":4: stamp goes backwards"), std::string::npos) << run.output;
}

// The official TUM RGB-D fr2/desk ground truth repeats one stamp (lines 10862-10863): evaluated by default.
TEST(Cli, TumFr2DeskGroundTruthEvaluatesByDefault) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: this test needs fr2_desk_groundtruth.txt";
  testing::TempDir dir;
  const std::string gt = data + "/trajectories/fr2_desk_groundtruth.txt";
  const std::string estimate = data + "/trajectories/fr2_desk_ORB_kf_mono.txt";
  CommandResult run =
      Ultrafusion("eval " + gt + " " + estimate + " --align sim3 --json " + dir.File("e.json"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find(gt + ": skipped 1 poses repeating the previous stamp, kept the first of each "
                                 "(first skipped on line 10863"),
            std::string::npos)
      << run.output;
  const auto json = nlohmann::json::parse(testing::ReadText(dir.File("e.json")));
  EXPECT_EQ(json["skipped_duplicate_stamps"]["reference"].get<int>(), 1);
  // evo_ape tum fr2_desk_groundtruth.txt fr2_desk_ORB_kf_mono.txt -as (as in test_evo_agreement.cpp).
  EXPECT_EQ(json["ape"]["n"].get<int>(), 118);
  EXPECT_NEAR(json["ape"]["rmse"].get<double>(), 0.007729264783424089, 1e-6 * 0.0077);
  run = Ultrafusion("eval " + gt + " " + estimate + " --strict-stamps");
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find(gt + ":10863: duplicate stamp 1311868229.576000000 s"), std::string::npos)
      << run.output;
}

TEST(Cli, KittiWithTimesAndDrift) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: this test needs KITTI_00_gt.txt";
  const std::string gt = data + "/trajectories/KITTI_00_gt.txt",
                    times = data + "/trajectories/KITTI_00_gt_times.txt";
  const CommandResult run = Ultrafusion("eval " + gt + " " + gt + " --ref-times " + times + " --est-times " +
                                        times + " --kitti-drift");
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("matched:   4541 pairs"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("KITTI drift: 0.0000 % translation"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace uf
