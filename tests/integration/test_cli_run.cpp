// `ultrafusion run` as a user runs it: LiDAR, LiDAR-inertial and wheel-inertial odometry over a small
// simulated sequence, every output file parsed back, the accuracy against ground truth, and bad input (exit
// codes, messages). The recorded datasets: test_cli_run_recorded.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/run_outputs.h"
#include "tests/support/simulated_sequence.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::ReadRows;
using testing::ReportedAte;
using testing::TempDir;

class CliRun : public testing::SimulatedSequenceTest {};

TEST_F(CliRun, LidarOdometryOnASimulatedSequenceWritesEveryOutput) {
  TempDir out;
  const std::string run = out.File("run");
  const auto result = Ultrafusion("run " + Sequence() + " --mode lo --no-map --no-splat --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  for (const char* file : {"trajectory.tum", "trajectory_kitti.txt", "timing.json", "config.yaml",
                           "report.md", "plots/ape_top_view.png", "plots/ape_over_time.png",
                           "reliability.csv", "plots/reliability_lidar.png"})
    EXPECT_TRUE(fs::exists(run + "/" + file)) << file;
  EXPECT_FALSE(fs::exists(run + "/imu_states.csv"));  // LO estimates no inertial state
  // One LiDAR row per registered scan (all but the first), each with its score in [0, 1].
  std::istringstream reliability(testing::ReadText(run + "/reliability.csv"));
  std::string line;
  std::getline(reliability, line);
  EXPECT_EQ(line.rfind("stamp_ns,modality,score,active,", 0), 0u) << line;
  int rows = 0;
  while (std::getline(reliability, line)) {
    ++rows;
    const std::size_t modality = line.find(",lidar,");
    ASSERT_NE(modality, std::string::npos) << line;
    const double score = std::stod(line.substr(modality + 7));
    EXPECT_TRUE(score >= 0 && score <= 1) << line;
  }
  EXPECT_GE(rows, 30);
  const std::string reliability_report = testing::ReadText(run + "/report.md");
  EXPECT_NE(reliability_report.find("## Reliability (LiDAR degeneracy)"), std::string::npos);
  EXPECT_NE(reliability_report.find("![LiDAR degeneracy](plots/reliability_lidar.png)"), std::string::npos);

  // 4 s of 10 Hz scans: one pose per scan (none skipped on clean data), 8 numbers per TUM line, 12 per
  // KITTI line, stamps increasing.
  const auto tum = ReadRows(run + "/trajectory.tum");
  const auto kitti = ReadRows(run + "/trajectory_kitti.txt");
  ASSERT_GE(tum.size(), 35u);
  ASSERT_EQ(tum.size(), kitti.size());
  for (std::size_t i = 0; i < tum.size(); ++i) {
    ASSERT_EQ(tum[i].size(), 8u) << "line " << i + 1;
    ASSERT_EQ(kitti[i].size(), 12u) << "line " << i + 1;
    if (i > 0) {
      EXPECT_GT(tum[i][0], tum[i - 1][0]);
    }
    EXPECT_NEAR(tum[i][1], kitti[i][3], 1e-8);  // x translation in both files (9 vs 12 decimals)
  }

  const auto timing = nlohmann::json::parse(testing::ReadText(run + "/timing.json"));
  EXPECT_EQ(timing["scans"].get<std::size_t>(), tum.size() + timing["skipped"].get<std::size_t>());
  for (const char* key : {"mean", "median", "p95", "max"})
    EXPECT_GT(timing["ms_per_scan"][key].get<double>(), 0);
  EXPECT_LE(timing["ms_per_scan"]["median"].get<double>(), timing["ms_per_scan"]["max"].get<double>());
  EXPECT_TRUE(timing.contains("warnings"));
  // Where the scans' time went: each stage's mean, together at most the mean per scan (the rest is the
  // scan's bookkeeping between the stages).
  double stages = 0;
  for (const char* key : {"prepare", "associate", "register", "window", "map", "marginalize"}) {
    const double ms = timing["stage_ms_mean"][key].get<double>();
    EXPECT_GE(ms, 0) << key;
    stages += ms;
  }
  EXPECT_GT(timing["stage_ms_mean"]["associate"].get<double>(), 0);
  EXPECT_LE(stages, timing["ms_per_scan"]["mean"].get<double>());

  // Ground truth is the body (IMU) frame, the estimate the LiDAR frame 0.25 m above it with the same
  // rotation: after SE3 alignment the offset only matters through rotation, so a working LO is at
  // centimetres; a broken one (lost track, wrong deskew) is at metres.
  const std::string report = testing::ReadText(run + "/report.md");
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0) << report;
  EXPECT_LT(ate, 0.5) << report;
  EXPECT_NE(report.find("--no-map"), std::string::npos);
  EXPECT_NE(report.find("lo:"), std::string::npos);
  EXPECT_NE(report.find("Mean per scan by stage [ms]: preparation "), std::string::npos);

  // The saved configuration is accepted as --config (here with an output folder that makes it stop early).
  const auto again =
      Ultrafusion("run " + Sequence() + " --config " + run + "/config.yaml --mode lo --out " + run);
  EXPECT_EQ(again.code, 2) << again.output;
  EXPECT_NE(again.output.find("not an empty folder"), std::string::npos) << again.output;
}

TEST_F(CliRun, AutoModeRunsLidarInertialOdometryWithWheelAndGnssFactorsInTheImuFrame) {
  TempDir out;
  const std::string run = out.File("run");
  const auto result = Ultrafusion("run " + Sequence() + " --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  // The sequence has an IMU, wheel and GNSS streams and their extrinsics: auto takes the richest mode.
  EXPECT_NE(result.output.find("run: lwgio (LiDAR-inertial odometry with wheel and GNSS factors"),
            std::string::npos)
      << result.output;
  const std::string report = testing::ReadText(run + "/report.md");
  EXPECT_NE(
      report.find("wheel factors: 40 added, 0 skipped (no wheel samples over the interval), 0 left out"),
      std::string::npos)
      << report;
  // The wheel's reliability scheduling scored the interval ending at each mapped scan from 1 s after the
  // initialization on (change_window_s; an ideal encoder: none left out): a wheel row beside most LiDAR rows
  // of reliability.csv (measured 28), and the report's section.
  std::istringstream reliability(testing::ReadText(run + "/reliability.csv"));
  std::string line;
  std::getline(reliability, line);
  int wheel_rows = 0, lidar_rows = 0;
  while (std::getline(reliability, line)) {
    wheel_rows += line.find(",wheel,") != std::string::npos;
    lidar_rows += line.find(",lidar,") != std::string::npos;
  }
  EXPECT_GE(wheel_rows, 25);
  EXPECT_LE(wheel_rows, lidar_rows + 1);
  EXPECT_NE(report.find("## Reliability (wheel)"), std::string::npos) << report;
  EXPECT_NE(report.find("0 of " + std::to_string(wheel_rows) + " scored intervals left out."),
            std::string::npos)
      << report;
  // 4 s from rest: the antenna moves less than the 10 m the ENU alignment needs, so no GNSS factor yet, no
  // georeference, and the trajectory stays in the estimator's world.
  EXPECT_NE(report.find("GNSS factors: 0 added"), std::string::npos) << report;
  EXPECT_NE(report.find("horizontal baseline"), std::string::npos) << report;
  EXPECT_FALSE(fs::exists(run + "/trajectory_wgs84.csv"));
  // 1 s at rest first: static after the second scan; the console says so too.
  EXPECT_NE(report.find("LIO initialized: S (static) after 0.2 s"), std::string::npos) << report;
  EXPECT_NE(result.output.find("  initialized: S (static) after 0.2 s"), std::string::npos) << result.output;
  // The stationary branch holds the intervals at rest after the initialization (0.2 s to the drive-off at
  // 1 s: 8, give or take the one where the wheels start to turn).
  const std::size_t held = report.find(" intervals held at rest (the wheels read no motion");
  ASSERT_NE(held, std::string::npos) << report;
  const int held_intervals = std::stoi(report.substr(report.rfind(' ', held - 1) + 1));
  EXPECT_GE(held_intervals, 7);
  EXPECT_LE(held_intervals, 9);
  // The inertial states: a row per keyframe, and the speed of those the branch held (0.3-0.9 s, after the
  // initialization's first two scans) within its 5 mm/s.
  ASSERT_TRUE(fs::exists(run + "/plots/imu_accel_bias.png"));
  ASSERT_TRUE(fs::exists(run + "/plots/imu_gyro_bias.png"));
  std::istringstream states(testing::ReadText(run + "/imu_states.csv"));
  std::getline(states, line);
  EXPECT_EQ(line.rfind("stamp_ns,vx_mps,vy_mps,vz_mps,speed_mps,accel_bias_x,", 0), 0u) << line;
  int state_rows = 0;
  while (std::getline(states, line)) {
    ++state_rows;
    std::istringstream fields(line);
    std::string stamp, speed;
    std::getline(fields, stamp, ',');
    for (int k = 1; k < 5; ++k) std::getline(fields, speed, ',');  // the fifth: speed_mps
    const double t = 1e-9 * static_cast<double>(std::stoll(stamp) - 1'700'000'000'000'000'000);
    if (t > 0.3 && t < 0.9) {
      EXPECT_LT(std::stod(speed), 0.005) << line;
    }
  }
  EXPECT_GE(state_rows, 37);
  EXPECT_NE(report.find("## Inertial states"), std::string::npos) << report;
  EXPECT_NE(report.find("![Gyroscope bias](plots/imu_gyro_bias.png)"), std::string::npos) << report;
  EXPECT_NE(report.find("lio:"), std::string::npos) << report;  // the resolved config
  // A 16-beam LiDAR: the ring gate's auto keeps one-ring planes (docs/METHOD.md "Voxel-hash map and PCA
  // planes").
  EXPECT_NE(
      report.find("LiDAR map: planes from blocks of any number of LiDAR rings (lo.map.min_plane_rings "
                  "auto: the scans' rings are unknown or fewer than 32; with a sparse LiDAR outdoors, 2 "
                  "keeps the map from tilting"),
      std::string::npos)
      << report;
  // LIO writes the IMU (body) frame by default, the frame of the ground truth.
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0);
  EXPECT_LT(ate, 0.1) << report;

  // The map stage: map.vdb and its exports; no camera in this sequence, so the map is uncoloured, and the
  // report says so.
  for (const char* file : {"map.vdb", "map.ply", "map.las", "map.glb", "georef.json"})
    EXPECT_TRUE(fs::exists(run + "/" + file)) << file;
  EXPECT_NE(report.find("no calibrated camera: the map is written without colour"), std::string::npos)
      << report;
  const std::string ply_header = testing::ReadText(run + "/map.ply").substr(0, 400);
  EXPECT_EQ(ply_header.rfind("ply\nformat binary_little_endian 1.0", 0), 0u) << ply_header;

  // `export` writes the map again from map.vdb, here points only as PLY into another folder.
  const std::string again = out.File("again");
  const auto exported = Ultrafusion("export " + run + " --format ply --out " + again);
  ASSERT_EQ(exported.code, 0) << exported.output;
  EXPECT_EQ(testing::ReadText(again + "/map.ply"), testing::ReadText(run + "/map.ply"));
  EXPECT_FALSE(fs::exists(again + "/map.las"));
  const auto utm = Ultrafusion("export " + run + " --crs utm --out " + out.File("utm"));
  EXPECT_EQ(utm.code, 1) << utm.output;
  EXPECT_NE(utm.output.find("no georeference"), std::string::npos) << utm.output;
  const auto format = Ultrafusion("export " + run + " --format ply,xyz --out " + out.File("xyz"));
  EXPECT_EQ(format.code, 2) << format.output;
  EXPECT_NE(format.output.find("unknown format 'xyz'"), std::string::npos) << format.output;
  const auto no_map = Ultrafusion("export " + out.File("nothing") + " --out " + out.File("none"));
  EXPECT_EQ(no_map.code, 1) << no_map.output;
  EXPECT_NE(no_map.output.find("no map in the run folder"), std::string::npos) << no_map.output;

  // A bad lio: value is a usage error that names it.
  const std::string config = out.Write("bad.yaml", "lio:\n  imu:\n    gravity: -9.8\n");
  const auto bad = Ultrafusion("run " + Sequence() + " --config " + config + " --out " + out.File("bad"));
  EXPECT_EQ(bad.code, 2) << bad.output;
  EXPECT_NE(bad.output.find("lio.imu.gravity"), std::string::npos) << bad.output;
}

TEST_F(CliRun, WheelInertialModeRunsOnTheImuAndTheWheelAlone) {
  TempDir out;
  const std::string run = out.File("run");
  const auto result = Ultrafusion("run " + Sequence() + " --mode wio --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("run: wio (wheel-inertial odometry on imu, wheel), "), std::string::npos)
      << result.output;
  // No LiDAR in the estimator: no map, no splats; a pose every 0.1 s node of IMU time from the start at rest.
  EXPECT_NE(result.output.find("map skipped (wio: no LiDAR keyframes to map)"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(run + "/map.vdb"));
  const auto tum = ReadRows(run + "/trajectory.tum");
  ASSERT_GE(tum.size(), 30u);
  for (std::size_t i = 1; i < tum.size(); ++i) EXPECT_NEAR(tum[i][0] - tum[i - 1][0], 0.1, 1e-6) << i;
  const auto timing = nlohmann::json::parse(testing::ReadText(run + "/timing.json"));
  EXPECT_GT(timing["nodes"].get<std::size_t>(), 0u);
  EXPECT_GT(timing["ms_per_node"]["mean"].get<double>(), 0);
  EXPECT_TRUE(fs::exists(run + "/plots/timing_per_node.png"));
  const std::string report = testing::ReadText(run + "/report.md");
  EXPECT_NE(report.find("WIO initialized: static"), std::string::npos) << report;  // 1 s at rest first
  EXPECT_NE(
      report.find("wheel factors: 40 added, 0 skipped (no wheel samples over the interval), 0 left out"),
      std::string::npos)
      << report;
  // The wheel's reliability scheduling scored every interval from 1 s after the initialization on
  // (change_window_s: 30 of the 40; an ideal encoder: none left out), in reliability.csv, its plot and the
  // report.
  EXPECT_NE(report.find("## Reliability (wheel)"), std::string::npos) << report;
  EXPECT_NE(report.find("0 of 30 scored intervals left out."), std::string::npos) << report;
  EXPECT_TRUE(fs::exists(run + "/plots/reliability_wheel.png"));
  std::istringstream reliability(testing::ReadText(run + "/reliability.csv"));
  std::string line;
  std::getline(reliability, line);
  EXPECT_NE(line.find(",speed_error_mps,speed_change_error_mps,yaw_rate_error_rad_s,"), std::string::npos)
      << line;
  int wheel_rows = 0, imu_rows = 0;
  while (std::getline(reliability, line)) {
    wheel_rows += line.find(",wheel,") != std::string::npos;
    imu_rows += line.find(",imu,") != std::string::npos;
  }
  EXPECT_EQ(wheel_rows, 30);
  // The IMU scored over the same intervals; no range configured, so nothing counts as clipped.
  EXPECT_EQ(imu_rows, 40);
  EXPECT_NE(report.find("## Reliability (IMU)"), std::string::npos) << report;
  EXPECT_NE(report.find("40 intervals scored"), std::string::npos) << report;
  EXPECT_NE(report.find("0 with clipped readings."), std::string::npos) << report;
  EXPECT_NE(report.find("wio:\n  node_interval_s: 0.1"), std::string::npos) << report;  // the wio: section
  EXPECT_EQ(report.find("\nlo:\n"), std::string::npos) << report;                       // and no lo:
  // Against the simulator's truth (the IMU frame, as WIO writes it): the wheel and the IMU over 3 s of
  // driving keep the track within centimetres; a broken window (wrong extrinsic, lost gravity) is at metres.
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0) << report;
  EXPECT_LT(ate, 0.05) << report;

  // With GNSS (wgio): 4 s are too short for the ENU alignment, which the report says.
  const auto wgio = Ultrafusion("run " + Sequence() + " --mode wgio --out " + out.File("wgio"));
  ASSERT_EQ(wgio.code, 0) << wgio.output;
  EXPECT_NE(testing::ReadText(out.File("wgio") + "/report.md").find("GNSS factors: 0 added"),
            std::string::npos);
  // Options a wheel-inertial run cannot honour are usage errors.
  const auto from_map = Ultrafusion("run " + Sequence() + " --mode wio --from map --out " + run);
  EXPECT_EQ(from_map.code, 2) << from_map.output;
  EXPECT_NE(from_map.output.find("--from map: wio makes no map"), std::string::npos) << from_map.output;
}

TEST(CliRunErrors, BadInputExitsWithAClearMessage) {
  TempDir dir;
  const auto missing = Ultrafusion("run " + dir.File("nothing-here") + " --mode lo --out " + dir.File("a"));
  EXPECT_EQ(missing.code, 1) << missing.output;
  EXPECT_FALSE(fs::exists(dir.File("a")));

  const std::string config = dir.Write("bad.yaml", "lo:\n  window_size: 4\n  window_sise: 3\n");
  const auto unknown =
      Ultrafusion("run " + dir.File("x") + " --config " + config + " --out " + dir.File("c"));
  EXPECT_EQ(unknown.code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("bad.yaml: lo.window_sise (line 3): unknown key"), std::string::npos)
      << unknown.output;

  const std::string bad_value = dir.Write("value.yaml", "lo:\n  map:\n    voxel_m: fast\n");
  const auto value =
      Ultrafusion("run " + dir.File("x") + " --config " + bad_value + " --out " + dir.File("d"));
  EXPECT_EQ(value.code, 2) << value.output;
  EXPECT_NE(value.output.find("lo.map.voxel_m (line 3): expected a number, got 'fast'"), std::string::npos)
      << value.output;

  fs::create_directories(dir.File("full"));
  dir.Write("full/file.txt", "keep me");
  const auto full = Ultrafusion("run " + dir.File("x") + " --mode lo --out " + dir.File("full"));
  EXPECT_EQ(full.code, 2) << full.output;
  EXPECT_EQ(testing::ReadText(dir.File("full/file.txt")), "keep me");

  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: no LiDAR-less bag to try";
  const std::string bag = data + "/husky-imu-wheel-gps/husky_watertown_2015-05-21.bag";
  // Without configs/husky.yaml the bag has no wheel extrinsic: neither a LiDAR mode nor WIO can run.
  const auto no_lidar = Ultrafusion("run " + bag + " --out " + dir.File("e"));
  EXPECT_EQ(no_lidar.code, 1) << no_lidar.output;
  EXPECT_NE(no_lidar.output.find("no LiDAR stream (for lo and lio) and no wheel-to-IMU transform"),
            std::string::npos)
      << no_lidar.output;
  EXPECT_NE(no_lidar.output.find("/imu/data (imu)"), std::string::npos) << no_lidar.output;
  EXPECT_FALSE(fs::exists(dir.File("e")));
  const auto lio = Ultrafusion("run " + bag + " --mode lio --out " + dir.File("e"));
  EXPECT_EQ(lio.code, 2) << lio.output;
  EXPECT_NE(lio.output.find("--mode lio: " + bag + " has no LiDAR stream"), std::string::npos) << lio.output;
}

}  // namespace
}  // namespace uf
