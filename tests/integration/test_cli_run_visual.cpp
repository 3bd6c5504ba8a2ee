// `ultrafusion run --mode vio` as a user runs it: the IMU and the camera of a short simulated drive, the
// front end's files, the report's visual lines and the accuracy; a damaged frame and a dataset without a
// camera; `--mode lvio` on a drive with the LiDAR too; a stereo rig in both windows.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "odometry/io/calibration_file.h"
#include "odometry/types/printf_text.h"
#include "tests/support/cli_runner.h"
#include "tests/support/run_outputs.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::ReportedAte;
using testing::TempDir;

// Lines of tracks.csv after its header.
std::size_t DataLines(const std::string& path) {
  std::istringstream text(testing::ReadText(path));
  std::size_t lines = 0;
  for (std::string line; std::getline(text, line);) lines += line.empty() ? 0 : 1;
  return lines - 1;
}

class CliRunVisual : public ::testing::Test {
 protected:
  // 6 s of the urban drive (1 s at rest, then off) with the IMU and the forward camera only.
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    const auto sim = Ultrafusion("sim --scene urban --duration 6 --lidar none --no-wheel --no-gnss --out " +
                                 dir_->File("seq"));
    ASSERT_EQ(sim.code, 0) << sim.output;
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static std::string Sequence() { return dir_->File("seq"); }
  static inline std::unique_ptr<TempDir> dir_;
};

TEST_F(CliRunVisual, VisualInertialModeTracksTheCameraAndReportsItsFactors) {
  TempDir out;
  const std::string run = out.File("run");
  const auto result = Ultrafusion("run " + Sequence() + " --out " + run);  // auto: vio
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("--mode auto: ran vio (no LiDAR stream, no wheel odometry stream, no GNSS "
                               "stream)"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("run: vio (visual-inertial odometry on imu, cam0), "), std::string::npos)
      << result.output;
  EXPECT_EQ(DataLines(run + "/tracks.csv"), 61u);  // every frame, 0 to 6 s at 10 Hz
  for (const char* plot :
       {"track_features", "track_ratio", "track_degeneracy", "timing_per_node", "visual_landmarks"})
    EXPECT_TRUE(fs::exists(run + "/plots/" + plot + ".png")) << plot;
  // The overlays of every 50th frame (the default --overlay-every): frames 0 and 50.
  EXPECT_TRUE(fs::exists(run + "/plots/tracks_1700000000000000000.png"));
  EXPECT_TRUE(fs::exists(run + "/plots/tracks_1700000005000000000.png"));
  EXPECT_FALSE(fs::exists(run + "/plots/tracks_1700000000100000000.png"));
  const std::string report = testing::ReadText(run + "/report.md");
  EXPECT_NE(report.find("WIO initialized: static"), std::string::npos) << report;
  EXPECT_NE(report.find("visual factors: "), std::string::npos) << report;
  EXPECT_NE(report.find("## Camera in the window\n\nLandmarks per node after its solve: mean "),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("camera time offset t_d 0.0000 s (fixed)"), std::string::npos) << report;
  EXPECT_NE(report.find("  visual:\n    stereo: true\n    pixel_sigma_px: 1"), std::string::npos) << report;
  // Against the simulator's truth: ~25 m of driving. Measured 0.035 m; the IMU alone drifts metres.
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0) << report;
  EXPECT_LT(ate, 0.1) << report;
}

TEST_F(CliRunVisual, AnEstimatedTimeOffsetIsWrittenAsACalibrationFile) {
  TempDir out;
  const std::string config = out.File("td.yaml");
  std::ofstream(config) << "wio:\n  visual:\n    estimate_time_offset: true\n";
  const std::string run = out.File("run");
  const auto result = Ultrafusion("run " + Sequence() + " --mode vio --config " + config + " --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  Expected<Calibration> calibration = ReadCalibrationFile(run + "/calibration_estimated.yaml");
  ASSERT_TRUE(calibration.ok()) << calibration.error();
  const SensorCalibration* camera = calibration->Find("cam0");
  ASSERT_NE(camera, nullptr);
  ASSERT_NE(camera->camera_model, nullptr);  // the intrinsics come along: the file is a whole calibration
  // The sequence's camera has no delay. Over 6 s (a start from rest, no turn) t_d is barely observed: it
  // stays within its prior's sigma (0.05 s) of the start value 0 (over 60 s it comes within 1 ms,
  // docs/METHOD.md). The file holds the report's value.
  EXPECT_LT(std::abs(ToSeconds(camera->time_offset)), 0.05);
  EXPECT_NE(
      testing::ReadText(run + "/report.md")
          .find(PrintfText("camera time offset t_d %.4f s (estimated)", ToSeconds(camera->time_offset))),
      std::string::npos);
}

TEST_F(CliRunVisual, ADamagedFrameIsSkippedWithAWarning) {
  TempDir out;
  const std::string data = out.File("damaged");
  fs::copy(Sequence(), data, fs::copy_options::recursive);
  const std::string frame = data + "/cam0/1700000003000000000.png";
  ASSERT_TRUE(fs::exists(frame));
  fs::resize_file(frame, 100);  // truncated
  const auto result = Ultrafusion("run " + data + " --mode vio --out " + out.File("run"));
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_EQ(DataLines(out.File("run") + "/tracks.csv"), 60u);
  const std::string report = testing::ReadText(out.File("run") + "/report.md");
  EXPECT_NE(report.find("frame at 1700000003.000000 s: image 'png': cannot decode 100 bytes"),
            std::string::npos)
      << report;
}

TEST(CliRunLidarVisual, LidarVisualModeAddsTheCameraToLioAndStillColoursTheMap) {
  // 6 s of the urban drive with the 16-beam LiDAR, the IMU and the camera.
  TempDir out;
  const std::string data = out.File("seq");
  const auto sim =
      Ultrafusion("sim --scene urban --duration 6 --lidar spinning16 --no-wheel --no-gnss --out " + data);
  ASSERT_EQ(sim.code, 0) << sim.output;
  const std::string run = out.File("run");
  const auto result = Ultrafusion("run " + data + " --mode lvio --no-splat --out " + run);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("run: lvio (LiDAR-visual-inertial odometry on lidar, imu, cam0), "),
            std::string::npos)
      << result.output;
  EXPECT_EQ(DataLines(run + "/tracks.csv"), 61u);  // every frame, 0 to 6 s at 10 Hz
  EXPECT_TRUE(fs::exists(run + "/plots/visual_landmarks.png"));
  const std::string report = testing::ReadText(run + "/report.md");
  EXPECT_NE(report.find("| odometry | LiDAR, IMU and camera streams |"), std::string::npos) << report;
  EXPECT_NE(report.find("landmarks took their depth from the LiDAR map"), std::string::npos) << report;
  EXPECT_NE(report.find("## Camera in the window\n\nLandmarks per scan after its solve: mean "),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("lio:\n"), std::string::npos) << report;
  // The frames the window tracks colour the map too (measured 98.8 % of the in-image points).
  EXPECT_NE(report.find("% of the in-image points coloured"), std::string::npos) << report;
  EXPECT_EQ(report.find(" 0.0 % of the in-image points coloured"), std::string::npos) << report;
  // Against the simulator's truth: ~25 m of driving. Measured 0.019 m.
  const double ate = ReportedAte(report);
  EXPECT_GE(ate, 0) << report;
  EXPECT_LT(ate, 0.04) << report;
}

TEST(CliRunStereo, AStereoRigAddsTheRightCamerasFactorsInBothWindows) {
  // 4 s of the urban drive with the 16-beam LiDAR, the IMU and a stereo rig 0.3 m wide.
  TempDir out;
  const std::string data = out.File("seq");
  const auto sim = Ultrafusion(
      "sim --scene urban --duration 4 --lidar spinning16 --no-wheel --no-gnss "
      "--stereo-baseline 0.3 --out " +
      data);
  ASSERT_EQ(sim.code, 0) << sim.output;
  for (const std::string mode : {"vio", "lvio"}) {
    const std::string run = out.File(mode);
    const auto result = Ultrafusion("run " + data + " --mode " + mode + " --no-map --out " + run);
    ASSERT_EQ(result.code, 0) << result.output;
    const std::string report = testing::ReadText(run + "/report.md");
    EXPECT_NE(report.find("stereo: cam0 with cam1 (baseline 0.300 m)"), std::string::npos) << report;
    // Every frame's pair (0 to 4 s at 10 Hz) in VIO; LVIO's window takes the frames once it started.
    const std::string pairs = mode == "vio" ? "; stereo: 41 frame pairs matched, " : " frame pairs matched, ";
    EXPECT_NE(report.find(pairs), std::string::npos) << report;
    EXPECT_EQ(report.find("; stereo: 0 frame pairs"), std::string::npos) << report;
    EXPECT_GE(ReportedAte(report), 0) << report;
  }
  // wio.visual.stereo: false leaves the rig's right camera out.
  const std::string config = out.File("mono.yaml");
  std::ofstream(config) << "wio:\n  visual:\n    stereo: false\n";
  const auto mono =
      Ultrafusion("run " + data + " --mode vio --config " + config + " --out " + out.File("mono"));
  ASSERT_EQ(mono.code, 0) << mono.output;
  const std::string report = testing::ReadText(out.File("mono") + "/report.md");
  EXPECT_EQ(report.find("stereo: cam0"), std::string::npos) << report;
  EXPECT_EQ(report.find("frame pairs matched"), std::string::npos) << report;
}

TEST_F(CliRunVisual, AModeWithTheCameraNeedsOne) {
  TempDir out;
  const std::string data = out.File("no-camera");
  const auto sim =
      Ultrafusion("sim --scene urban --duration 2 --lidar none --no-camera --no-gnss --out " + data);
  ASSERT_EQ(sim.code, 0) << sim.output;
  const auto result = Ultrafusion("run " + data + " --mode vwio --out " + out.File("run"));
  EXPECT_EQ(result.code, 2) << result.output;
  EXPECT_NE(result.output.find("--mode vwio: " + data + " has no camera stream with intrinsics"),
            std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace uf
