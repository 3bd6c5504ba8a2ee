// `ultrafusion run` as a user runs it: LiDAR odometry over a small simulated sequence and the first KITTI
// keyframes, every output file parsed back, the accuracy against ground truth, and bad input (exit codes,
// messages).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/simulated_sequence.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::TempDir;

// Numbers on each non-comment line of a text file.
std::vector<std::vector<double>> ReadRows(const std::string& path) {
  std::vector<std::vector<double>> rows;
  std::istringstream text(testing::ReadText(path));
  std::string line;
  while (std::getline(text, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    for (double v; fields >> v;) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

// The number after "ATE (APE translation RMSE, SE3-aligned): " in report.md, or -1.
double ReportedAte(const std::string& report) {
  const std::string key = "ATE (APE translation RMSE, SE3-aligned): ";
  const std::size_t at = report.find(key);
  if (at == std::string::npos) return -1;
  return std::stod(report.substr(at + key.size()));
}

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

  // Ground truth is the body (IMU) frame, the estimate the LiDAR frame 0.25 m above it with the same
  // rotation: after SE3 alignment the offset only matters through rotation, so a working LO is at
  // centimetres; a broken one (lost track, wrong deskew) is at metres.
  const std::string report = testing::ReadText(run + "/report.md");
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0) << report;
  EXPECT_LT(ate, 0.5) << report;
  EXPECT_NE(report.find("--no-map"), std::string::npos);
  EXPECT_NE(report.find("lo:"), std::string::npos);

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
  // The wheel's reliability scheduling scored the interval ending at each mapped scan (an ideal encoder:
  // none left out): a wheel row beside each LiDAR row of reliability.csv, and the report's section.
  std::istringstream reliability(testing::ReadText(run + "/reliability.csv"));
  std::string line;
  std::getline(reliability, line);
  int wheel_rows = 0, lidar_rows = 0;
  while (std::getline(reliability, line)) {
    wheel_rows += line.find(",wheel,") != std::string::npos;
    lidar_rows += line.find(",lidar,") != std::string::npos;
  }
  EXPECT_GE(wheel_rows, 35);
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
  EXPECT_NE(report.find("lio:"), std::string::npos) << report;  // the resolved config
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
  // The wheel's reliability scheduling scored every interval after the start (an ideal encoder: none left
  // out), in reliability.csv, its plot and the report.
  EXPECT_NE(report.find("## Reliability (wheel)"), std::string::npos) << report;
  EXPECT_NE(report.find("0 of 40 scored intervals left out."), std::string::npos) << report;
  EXPECT_TRUE(fs::exists(run + "/plots/reliability_wheel.png"));
  std::istringstream reliability(testing::ReadText(run + "/reliability.csv"));
  std::string line;
  std::getline(reliability, line);
  EXPECT_NE(line.find(",speed_error_mps,speed_change_error_mps,yaw_rate_error_rad_s,"), std::string::npos)
      << line;
  int wheel_rows = 0;
  while (std::getline(reliability, line)) wheel_rows += line.find(",wheel,") != std::string::npos;
  EXPECT_EQ(wheel_rows, 40);
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

TEST(CliRunKitti, FirstTenKeyframesRunAndReportTheAccuracy) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the KITTI keyframes are not available";
  TempDir dir;
  const fs::path source = fs::path(data) / "kitti00-keyframes";
  const fs::path copy = dir.path() / "kitti10";
  fs::create_directories(copy / "velodyne");
  std::ifstream times(source / "times.txt");
  std::ofstream first_times(copy / "times.txt");
  std::string line;
  for (int i = 0; i < 10 && std::getline(times, line); ++i) {
    first_times << line << "\n";
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.pcd", i);
    fs::copy_file(source / "velodyne" / name, copy / "velodyne" / name);
  }
  first_times.close();
  fs::copy_file(source / "groundtruth_velodyne.tum", copy / "groundtruth_velodyne.tum");

  const std::string run = dir.File("run");
  const auto result = Ultrafusion("run " + copy.string() + " --config " + std::string(UF_SOURCE_DIR) +
                                  "/configs/kitti.yaml --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_EQ(ReadRows(run + "/trajectory.tum").size(), 10u);
  const double ate = ReportedAte(testing::ReadText(run + "/report.md"));
  EXPECT_GE(ate, 0) << testing::ReadText(run + "/report.md");
  // The point time convention, checked on the scans, is said in the log and the report and kept in
  // config.yaml (so that a repeat derives the same times without checking again).
  const std::string said =
      "point times of velodyne: clockwise from behind (chosen by the check on the first scans";
  EXPECT_NE(result.output.find(said), std::string::npos) << result.output;
  EXPECT_NE(testing::ReadText(run + "/report.md").find(said), std::string::npos);
  EXPECT_NE(testing::ReadText(run + "/config.yaml").find("point_time_convention: clockwise_from_behind"),
            std::string::npos);
  // 18 m driven in 1.9 s. Only "not lost" is asserted here (LO's accuracy is its own tests' and bench's
  // business): a track lost at the first turn or a frame mix-up is off by several metres.
  EXPECT_LT(ate, 3.0);

  // KITTI has no IMU: --mode lio is an error naming what is missing, auto runs LO.
  const auto lio = Ultrafusion("run " + copy.string() + " --mode lio --out " + dir.File("lio"));
  EXPECT_EQ(lio.code, 2) << lio.output;  // a usage error: the mode asks for what the data lacks
  EXPECT_NE(lio.output.find("has no IMU stream"), std::string::npos) << lio.output;
  EXPECT_FALSE(fs::exists(dir.File("lio")));
  // --mode wgio names every stream it misses, the GNSS among them.
  const auto wgio = Ultrafusion("run " + copy.string() + " --mode wgio --out " + dir.File("wgio"));
  EXPECT_EQ(wgio.code, 2) << wgio.output;
  EXPECT_NE(wgio.output.find("has no IMU stream, no wheel odometry stream, no GNSS stream"),
            std::string::npos)
      << wgio.output;
  EXPECT_FALSE(fs::exists(dir.File("wgio")));
}

// The real KITTI raw drive end to end (issue 25): LIO+G on the HDL-64E and the 10 Hz OXTS, the map
// coloured from image_02, splats trained on the real images for a few dozen iterations at the default
// reduced resolution, and the accuracy against the OXTS reference the reader derives.
TEST(CliRunKittiRaw, TheRealDriveRunsEndToEndAndItsSplatsLearnFromTheImages) {
  const std::string data = testing::SharedData();
  const fs::path drive = fs::path(data) / "kitti-raw-0009" / "2011_09_26" / "2011_09_26_drive_0009_sync";
  if (data.empty() || !fs::exists(drive)) GTEST_SKIP() << "../shared/data/kitti-raw-0009 is absent";
  TempDir dir;
  const std::string config = dir.File("splat.yaml");
  // As configs/kitti-raw.yaml (exposure compensation), with the exposures fitted from iteration 30 on.
  std::ofstream(config) << "splat:\n  iterations: 60\n  exposure_compensation: true\n  exposure_from: 30\n";
  const std::string run = dir.File("run");
  const auto result = Ultrafusion("run " + drive.string() + " --config " + config + " --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  // 51 scans, 55 m at 10.7 m/s; the reference is decimetre-accurate, the figure is 0.20 m.
  const std::string report = testing::ReadText(run + "/report.md");
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0) << report;
  EXPECT_LT(ate, 0.2) << report;
  // The reference at the trajectory's stamps: all but the first, which precedes the first OXTS record (the
  // OXTS lags the scanner's trigger by 12-19 ms; no extrapolation).
  EXPECT_EQ(ReadRows(run + "/reference.tum").size() + 1, ReadRows(run + "/trajectory.tum").size());
  // The colour map: the share of the LiDAR points inside an image's footprint that took a colour.
  const std::size_t at = result.output.find(" % of the in-image points coloured");
  ASSERT_NE(at, std::string::npos) << result.output;
  EXPECT_GT(std::stod(result.output.substr(result.output.rfind(' ', at - 1) + 1)), 90.0) << result.output;
  // Splats: the 26 images, 1 before the trajectory's first pose, 25 used: 4 held out (index % 8 == 0).
  const auto metrics = nlohmann::json::parse(testing::ReadText(run + "/metrics.json"));
  EXPECT_EQ(metrics["views_test"].get<int>(), 4);
  EXPECT_EQ(metrics["views_train"].get<int>(), 21);
  EXPECT_EQ(metrics["resolution"], nlohmann::json::array({310, 93}));
  EXPECT_EQ(metrics["iterations"].get<int>(), 60);
  EXPECT_GT(metrics["psnr_test"].get<double>(), metrics["psnr_test_initial"].get<double>() + 1.0) << metrics;
  ASSERT_EQ(metrics["exposures"].size(), 25u);  // every view; the held-out ones interpolated
  for (const auto& exposure : metrics["exposures"])
    for (int c = 0; c < 3; ++c) {  // the Flea2's automatic exposure moves by a few tens of percent at most
      EXPECT_GT(exposure["gain"][c].get<double>(), 0.7) << exposure;
      EXPECT_LT(exposure["gain"][c].get<double>(), 1.3) << exposure;
    }
  EXPECT_EQ(metrics["masked_pixels"].get<int>(), 0);  // rectified images: every pixel filled
  EXPECT_TRUE(fs::exists(run + "/splats.ply"));
}

// The number after "against the GNSS track (... ): horizontal RMSE " in run's output, or -1.
double GnssTrackHorizontalRmse(const std::string& output) {
  const std::size_t at = output.find("against the GNSS track (");
  if (at == std::string::npos) return -1;
  const std::string key = "horizontal RMSE ";
  const std::size_t value = output.find(key, at);
  return value == std::string::npos ? -1 : std::stod(output.substr(value + key.size()));
}

TEST(CliRunHusky, WheelInertialOdometryOnARealRobotAgainstItsGnssTrack) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: no Husky bag";
  // The Husky bag (IMU 30 Hz, wheel 10 Hz, GNSS 2.5 Hz, 395 s, 395 m of track, no LiDAR) with the profile
  // that states what the bag itself shows (wheel extrinsic and delay, IMU noise).
  const std::string bag = data + "/husky-imu-wheel-gps/husky_watertown_2015-05-21.bag";
  const std::string config = std::string(UF_SOURCE_DIR) + "/configs/husky.yaml";
  TempDir out;
  // WGIO (auto): georeferenced by the estimator, every fix used (their heights, tens of metres off over
  // minutes, only horizontally): against the fixes, unaligned, within about their own sigma (0.8-1.1 m).
  const auto wgio = Ultrafusion("run " + bag + " --config " + config + " --out " + out.File("wgio"));
  ASSERT_EQ(wgio.code, 0) << wgio.output;
  EXPECT_NE(wgio.output.find("run: wgio (wheel-inertial odometry with GNSS factors"), std::string::npos)
      << wgio.output;
  const double georeferenced = GnssTrackHorizontalRmse(wgio.output);
  EXPECT_GE(georeferenced, 0) << wgio.output;
  EXPECT_LT(georeferenced, 1.5) << wgio.output;
  EXPECT_TRUE(fs::exists(out.File("wgio") + "/trajectory_wgs84.csv"));
  EXPECT_TRUE(fs::exists(out.File("wgio") + "/plots/gnss_track_top_view.png"));
  // WIO: the IMU and the wheel alone, fitted to the fixes after the run: within 1.5 % of the track.
  const auto wio = Ultrafusion("run " + bag + " --config " + config + " --mode wio --out " + out.File("wio"));
  ASSERT_EQ(wio.code, 0) << wio.output;
  const double fitted = GnssTrackHorizontalRmse(wio.output);
  EXPECT_GE(fitted, 0) << wio.output;
  EXPECT_LT(fitted, 6.0) << wio.output;
  const std::string report = testing::ReadText(out.File("wio") + "/report.md");
  EXPECT_NE(report.find("WIO initialized: wheel-aided"), std::string::npos) << report;  // it starts moving
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
