// `ultrafusion sim` as a user runs it: outputs, the resolved config, a recorded KITTI trajectory driving the
// sensors, and bad input (exit codes, messages, nothing left behind).
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::TempDir;

// A fast sequence: 16 beams at 1 degree, a small camera.
const std::string kSmall = " --duration 2 --lidar spinning16 --config " + std::string(UF_SOURCE_DIR) +
                           "/tests/integration/sim_small.yaml";

TEST(CliSim, WritesTheDatasetTruthAndCalibrations) {
  TempDir dir;
  const std::string out = dir.File("seq");
  const auto result = Ultrafusion("sim --scene warehouse --out " + out + kSmall + " --lidar-stamp-delay 0.1");
  ASSERT_EQ(result.code, 0) << result.output;
  for (const char* file :
       {"dataset.yaml", "imu.csv", "lidar.bin", "cam0/cam0.csv", "wheel.csv", "gnss.csv", "groundtruth.tum",
        "calibration_true.yaml", "calibration.yaml", "truth_imu_bias.csv", "sim_config.yaml"})
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  EXPECT_NE(result.output.find("sim: warehouse"), std::string::npos) << result.output;
  EXPECT_NE(testing::ReadText(out + "/calibration_true.yaml").find("time_offset_s: -0.100000000"),
            std::string::npos);

  // The dataset reads back, and the saved config repeats the run exactly.
  const auto info = Ultrafusion("info " + out);
  EXPECT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("lidar"), std::string::npos);
  const auto again = Ultrafusion("sim --config " + out + "/sim_config.yaml --out " + dir.File("again"));
  ASSERT_EQ(again.code, 0) << again.output;
  for (const char* file : {"lidar.bin", "imu.csv", "gnss.csv", "cam0/cam0.csv", "sim_config.yaml"})
    EXPECT_EQ(testing::ReadText(out + "/" + file), testing::ReadText(dir.File("again/") + file)) << file;
}

TEST(CliSim, PrintConfigShowsTheResolvedSettings) {
  const auto result = Ultrafusion("sim --scene tunnel --seed 9 --no-gnss --print-config", false);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("scene: \"tunnel\""), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("seed: 9"), std::string::npos);
}

TEST(CliSim, HandheldWithKeyframes) {
  TempDir dir;
  const std::string out = dir.File("hh");
  const auto result =
      Ultrafusion("sim --scene wild --motion handheld --lidar-rate 2 --no-camera --out " + out + kSmall);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("motion: peak body rate"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("between consecutive scans up to"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("spline fit to the poses: max"), std::string::npos) << result.output;
  // Sweeps at 0, 0.5, 1 and 1.5 s of the 2; the dataset states the rate of the scans it holds.
  EXPECT_NE(result.output.find("  lidar             4       2.00"), std::string::npos) << result.output;
  const std::string dataset = testing::ReadText(out + "/dataset.yaml");
  EXPECT_NE(dataset.find("file: lidar.bin\n    rate_hz: 2\n"), std::string::npos) << dataset;
  // --motion handheld holds the device at 1.4 m; the saved config repeats the run exactly.
  const std::string saved = testing::ReadText(out + "/sim_config.yaml");
  for (const char* line : {"motion: handheld}", "body_height_m: 1.4\n", "keyframe_rate_hz: 2\n"})
    EXPECT_NE(saved.find(line), std::string::npos) << line << " in\n" << saved;
  const auto again = Ultrafusion("sim --config " + out + "/sim_config.yaml --out " + dir.File("again"));
  ASSERT_EQ(again.code, 0) << again.output;
  for (const char* file : {"lidar.bin", "imu.csv", "groundtruth.tum"})
    EXPECT_EQ(testing::ReadText(out + "/" + file), testing::ReadText(dir.File("again/") + file)) << file;

  // --body-height after --motion wins; --print-config shows both keys.
  const auto printed =
      Ultrafusion("sim --motion handheld --body-height 1.6 --lidar-rate 5 --print-config", false);
  ASSERT_EQ(printed.code, 0) << printed.output;
  for (const char* line : {"motion: handheld}", "body_height_m: 1.6\n", "keyframe_rate_hz: 5\n"})
    EXPECT_NE(printed.output.find(line), std::string::npos) << line << " in\n" << printed.output;

  auto bad = Ultrafusion("sim --lidar-rate 20 --out " + dir.File("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("sim.lidar.keyframe_rate_hz: must be in [0, sim.lidar.rate_hz = 10] (0: every "
                            "sweep), got 20"),
            std::string::npos)
      << bad.output;
  const std::string poses = dir.Write("poses.tum",
                                      "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n3 2 0 0 0 0 0 1\n"
                                      "4 3 0 0 0 0 0 1\n");
  bad = Ultrafusion("sim --motion handheld --trajectory " + poses + " --out " + dir.File("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("sim.trajectory.motion: handheld"), std::string::npos) << bad.output;
  bad = Ultrafusion("sim --motion walking --out " + dir.File("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("--motion"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir.File("bad")));
}

TEST(CliSim, FollowsARecordedKittiTrajectory) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the KITTI trajectory is not available";
  TempDir dir;
  const auto result = Ultrafusion("sim --scene urban --out " + dir.File("kitti") + kSmall + " --trajectory " +
                                  data + "/trajectories/KITTI_00_gt.txt");
  ASSERT_EQ(result.code, 0) << result.output;
  // KITTI_00_gt.txt line 21 (2 s in) has the camera at x -0.9609163 (right), y -0.5783595 (down),
  // z 17.26896 (forward) from the first pose, which is the identity. In the simulator's z-up convention that
  // is x 17.26896 (forward), y 0.9609163 (left), z 0.5783595 (up). The spline follows the poses to
  // millimetres.
  std::istringstream truth(testing::ReadText(dir.File("kitti/groundtruth.tum")));
  std::string line;
  std::vector<std::array<double, 8>> poses;
  while (std::getline(truth, line)) {
    std::array<double, 8> v{};
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                    &v[6], &v[7]) == 8)
      poses.push_back(v);
  }
  ASSERT_GT(poses.size(), 300u);
  const auto& first = poses.front();
  const auto& last = poses.back();
  EXPECT_NEAR(last[0] - first[0], 2.0, 1e-6);
  EXPECT_NEAR(last[1] - first[1], 17.26896, 5e-3);
  EXPECT_NEAR(last[2] - first[2], 0.9609163, 5e-3);
  EXPECT_NEAR(last[3] - first[3], 0.5783595, 5e-3);
}

TEST(CliSim, BadInputExitsWithAClearMessageAndLeavesNothing) {
  TempDir dir;
  const std::string out = dir.File("out");
  auto result = Ultrafusion("sim --scene moon --out " + out);
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("sim.scene: unknown scene 'moon' (urban, wild, warehouse, corridor, tunnel)"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(out));

  const std::string bad_key = dir.Write("bad.yaml", "sim:\n  lidar:\n    colour: red\n");
  result = Ultrafusion("sim --out " + out + " --config " + bad_key);
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("sim.lidar.colour"), std::string::npos) << result.output;

  const std::string bad_rate = dir.Write("rate.yaml", "sim:\n  imu:\n    rate_hz: -200\n");
  result = Ultrafusion("sim --out " + out + " --config " + bad_rate);
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("sim.imu.rate_hz: must be in (0, 10000], got -200"), std::string::npos)
      << result.output;

  const std::string few = dir.Write("few.tum", "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n");
  result = Ultrafusion("sim --out " + out + " --trajectory " + few);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("few.tum: 2 poses"), std::string::npos) << result.output;

  const std::string backwards = dir.Write("back.tum",
                                          "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n1.5 2 0 0 0 0 0 1\n"
                                          "3 3 0 0 0 0 0 1\n4 4 0 0 0 0 0 1\n");
  result = Ultrafusion("sim --out " + out + " --trajectory " + backwards);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("back.tum:3"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out));

  fs::create_directories(dir.File("full"));
  dir.Write("full/keep.txt", "x");
  result = Ultrafusion("sim --out " + dir.File("full"));
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("not an empty folder"), std::string::npos) << result.output;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.File("full")), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace uf
