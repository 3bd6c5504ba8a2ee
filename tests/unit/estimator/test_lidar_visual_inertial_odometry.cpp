// LiDAR-visual-inertial odometry (LVIO: the LiDAR window with the IMU and the camera) end to end on short
// simulated drives, against the simulator's ground truth and against LIO on the same sequence: the camera's
// landmarks take their depth from the LiDAR map, reproject within the tracks' error, and leave the accuracy
// at least LIO's; held on the map's planes they carry a corridor's axis that the scans hold loosely; dark
// frames leave the LiDAR and the IMU to carry the window; a bad configuration names the field.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <numbers>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/image_decode.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/estimator/lio_test_support.h"
#include "tests/unit/estimator/window_truth_support.h"

namespace uf::estimator {
namespace {

constexpr Stamp kSimStart = 1'700'000'000'000'000'000;  // the simulator's default start

// The scene's default drive (1 s at rest, then off) with the 16-beam LiDAR, the IMU and the forward
// camera; `adjust` changes the simulation first.
std::filesystem::path Simulate(const uf::testing::TempDir& dir, double duration_s, const std::string& scene,
                               const std::function<void(sim::SimulationConfig&)>& adjust = nullptr) {
  sim::SimulationConfig config;
  config.scene = scene;
  config.duration_s = duration_s;
  config.lidar.model.model = "spinning16";
  config.lidar.model.horizontal_resolution_deg = 0.4;
  config.wheel.enabled = config.gnss.enabled = false;
  if (adjust) adjust(config);
  const std::filesystem::path out = dir.path() / "sequence";
  auto summary = sim::GenerateSequence(config, out);
  EXPECT_TRUE(summary.ok()) << summary.error();
  return out;
}

struct WindowRun {
  std::vector<std::string> warnings;
  SensorFactorStats factors;
  int frames = 0;
  int min_landmarks = std::numeric_limits<int>::max();  // the fewest after a scan's solve, once moving
  double max_reprojection_px = 0;                       // the largest mean after a scan's solve
  double ate_m = std::numeric_limits<double>::infinity();
  std::size_t poses = 0;
};

// LIO, or LVIO with `camera`, over the folder; `edit` changes the window's configuration first.
WindowRun RunWindow(const std::filesystem::path& folder, bool camera,
                    const std::function<void(LidarOdometryConfig&)>& edit = nullptr) {
  WindowRun run;
  auto reader = OpenDataset(folder.string());
  EXPECT_TRUE(reader.ok()) << reader.error();
  if (!reader) return run;
  LidarOdometryConfig config = testing::SimulatedLioConfig();
  config.visual.max_solver_time_s = 10;  // only the iteration budget: the results do not depend on the load
  config.use_camera = camera;
  for (const StreamInfo& stream : (*reader)->description().streams)
    if (stream.kind == SensorKind::kCamera && stream.T_body_sensor) {
      config.camera = stream.camera_model;
      config.T_body_camera = *stream.T_body_sensor;
    }
  if (edit) edit(config);
  auto lvio = LidarOdometry::Create(config);
  EXPECT_TRUE(lvio.ok()) << lvio.error();
  if (!lvio) return run;
  Trajectory estimate;
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data)) return lvio->AddScan(*scan);
    if (const auto* sample = std::get_if<ImuSample>(&m.data)) return lvio->AddImu(*sample);
    if (auto* frame = std::get_if<CameraFrame>(&m.data); frame && camera) {
      if (Status s = DecodeCameraFrame(*frame); !s.ok()) return s;
      return lvio->AddCameraFrame(*frame);
    }
    return Status();
  });
  EXPECT_TRUE(read.ok()) << read.message();
  lvio->Finish();
  for (const OdometryStats& scan : lvio->TakeProcessedStats()) {
    if (!camera) {
      EXPECT_EQ(scan.landmarks, -1);
      continue;
    }
    run.max_reprojection_px = std::max(run.max_reprojection_px, scan.reprojection_px);
    if (scan.stamp - kSimStart > 3 * kNanosecondsPerSecond)  // moving, the window initialized
      run.min_landmarks = std::min(run.min_landmarks, scan.landmarks);
  }
  for (const Keyframe& k : lvio->TakeFinished()) {
    EXPECT_TRUE(k.T_world_body.matrix().allFinite()) << ToSeconds(k.stamp);
    estimate.stamps.push_back(k.stamp);
    estimate.poses.push_back(k.T_world_body);
  }
  run.frames = static_cast<int>(lvio->TakeTrackedFrames().size());
  run.warnings = lvio->warnings();
  run.factors = lvio->sensor_factors();
  run.poses = estimate.size();
  if (!estimate.empty()) run.ate_m = testing::AgainstTruth(folder, estimate).ate_m;
  return run;
}

using testing::Joined;

TEST(LidarVisualInertialOdometry, LandmarksTakeTheMapsDepthAndKeepLiosAccuracy) {
  // 12 s of the urban drive (~70 m).
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 12.0, "urban");
  const WindowRun lio = RunWindow(folder, false);
  const WindowRun lvio = RunWindow(folder, true);
  EXPECT_TRUE(lvio.warnings.empty()) << Joined(lvio.warnings);
  EXPECT_EQ(lvio.frames, 121);  // every frame tracked (0 to 12 s at 10 Hz)
  // Measured: at least 32 landmarks in the window after each scan once moving, 653 landmarks with the
  // map's depth over the run, 5967 reprojections, the worst scan's mean reprojection error 1.35 px.
  // Bounds: ~1.5x.
  EXPECT_GT(lvio.min_landmarks, 20);
  EXPECT_GT(lvio.factors.visual_map_depths, 400);
  EXPECT_GT(lvio.factors.visual.added, 4000);
  EXPECT_LT(lvio.max_reprojection_px, 2.0);
  // Measured: ATE 0.0087 m against LIO's 0.0106 m on the same sequence.
  EXPECT_LT(lvio.ate_m, lio.ate_m);
}

TEST(LidarVisualInertialOdometry, DarkFramesLeaveTheLidarAndImuToCarryTheWindow) {
  // Frames 5-8 s almost black (exposure x 0.001): no track survives, no landmark is made there, and the
  // window goes on with the LiDAR and the IMU.
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 10.0, "urban", [](sim::SimulationConfig& c) {
    c.camera.model.exposure_changes.push_back(
        {{kSimStart + 5'000'000'000, kSimStart + 8'000'000'000}, 0.001});
  });
  const WindowRun lio = RunWindow(folder, false);
  const WindowRun lvio = RunWindow(folder, true);
  EXPECT_EQ(lvio.frames, 101);  // every frame tracked, the dark ones without features
  EXPECT_EQ(lvio.poses, lio.poses);
  const std::string warnings = Joined(lvio.warnings);
  EXPECT_EQ(warnings.find("diverged"), std::string::npos) << warnings;
  EXPECT_EQ(warnings.find("rejected"), std::string::npos) << warnings;
  // Measured: ATE 0.0107 m against LIO's 0.0101 m (the landmarks start again after the dark frames).
  EXPECT_LT(lvio.ate_m, 1.2 * lio.ate_m) << "LIO " << lio.ate_m;
}

TEST(LidarVisualInertialOdometry, TheMapsPlanesLetTheCameraMeasureACorridorsAxis) {
  // 12 s of the corridor (1 s at rest, then off at 1.2 m/s) with the 16-beam LiDAR: its scans hold the
  // corridor's axis loosely, and LIO falls metres behind while the car pulls away (docs/METHOD.md "In the LIO
  // window: the corridor"). A landmark whose depth is only a start leaves the camera's motion up to scale;
  // held on the map's plane (the side walls: their distance is what the LiDAR does measure) its bearings
  // give the motion along the axis in metres (docs/METHOD.md "LiDAR-visual-inertial odometry").
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 12.0, "corridor");
  const WindowRun lio = RunWindow(folder, false);
  const WindowRun held = RunWindow(folder, true);
  const WindowRun free =
      RunWindow(folder, true, [](LidarOdometryConfig& c) { c.visual.hold_map_depth = false; });
  EXPECT_EQ(held.factors.visual_map_planes, held.factors.visual_map_depths);
  EXPECT_GT(held.factors.visual_map_planes, 500);
  EXPECT_EQ(free.factors.visual_map_planes, 0);
  // Measured: ATE 0.418 m held, 3.11 m with the depths free, LIO 2.71 m (1294 landmarks held). Bounds: 2x.
  EXPECT_LT(held.ate_m, 0.3 * lio.ate_m) << "held " << held.ate_m << ", LIO " << lio.ate_m;
  EXPECT_LT(held.ate_m, 0.3 * free.ate_m) << "held " << held.ate_m << ", free " << free.ate_m;
}

TEST(LidarVisualInertialOdometry, ACameraExtrinsicTwoDegreesOffIsEstimated) {
  // The dataset gives the camera's mount rotated by 2 deg from the truth (the simulator's calibration.yaml);
  // the window estimates T_imu_cam from it, with its prior of 2 deg and 1 cm.
  uf::testing::TempDir dir;
  const Eigen::Vector3d error_deg = Eigen::Vector3d(1, -1.5, 0.8).normalized() * 2;
  sim::SimulationConfig truth;
  const std::filesystem::path folder = Simulate(dir, 12.0, "urban", [&](sim::SimulationConfig& c) {
    c.camera.placement.rotation_error_deg = error_deg;
    truth = c;
  });
  const SE3 true_extrinsic = truth.camera.placement.T_body_sensor;
  const WindowRun lvio =
      RunWindow(folder, true, [](LidarOdometryConfig& c) { c.visual.estimate_extrinsic = true; });
  ASSERT_TRUE(lvio.factors.camera_extrinsic);
  const SE3 error = true_extrinsic.inverse() * *lvio.factors.camera_extrinsic;
  // The rotation error in the camera's frame, deg: off the optical axis (z) it is observed; about it (the
  // roll of a camera driving forward: its flow radiates from the image centre whatever the roll) only the
  // turns show it, and on this drive it is not held (docs/METHOD.md "LiDAR-visual-inertial odometry").
  const Eigen::Vector3d error_cam_deg = error.so3().Log() * 180 / std::numbers::pi;
  // Measured: 0.14 deg off the axis, 0.36 deg about it (0.81 given; 0.073 deg in all on the machine where
  // this was first measured: the weakly pinned roll differs between machines), 1 mm (the given
  // translation is the true one; the window's, weakly observed on a drive with few turns, stays within its
  // prior's 1 cm). Bounds: the 0.2 deg for a calibrated rotation, 5x the translation.
  EXPECT_LT(error_cam_deg.head<2>().norm(), 0.2) << error_cam_deg.transpose();
  EXPECT_LT(error.translation().norm(), 0.005);
}

TEST(LidarVisualInertialOdometry, ADelayedCameraIsFoundByTheMedianOfTheWindowsTimeOffsets) {
  // The camera stamps its frames 20 ms late (t_d = -0.02 s); the window estimates t_d from 0. Its landmarks
  // leave with their anchors, so each solve's t_d rests on the last ~1 s of them: it wanders by a few ms
  // while driving and by up to 0.1 s while pulling away, when the features barely move. The run's estimate
  // is the window's estimates' median weighted by the image motion that informs each (VisualProvider::
  // RecordWindowTimeOffset).
  uf::testing::TempDir dir;
  const std::filesystem::path folder =
      Simulate(dir, 12.0, "urban", [](sim::SimulationConfig& c) { c.camera.placement.stamp_delay_s = 0.02; });
  const WindowRun lvio =
      RunWindow(folder, true, [](LidarOdometryConfig& c) { c.visual.estimate_time_offset = true; });
  // Measured: -0.0201 s from 117 estimates (interquartile range 4.3 ms; the last window's -0.0194 s);
  // unweighted, the pull-away's estimates made the median -0.0127 s. Bound: the 2 ms.
  EXPECT_GT(lvio.factors.camera_time_offset_estimates, 80);  // one per scan once the camera joined
  EXPECT_NEAR(lvio.factors.camera_time_offset_s, -0.02, 0.002);
}

TEST(LidarVisualInertialOdometry, ConfigValidateNamesTheField) {
  const auto message = [](const std::function<void(LidarOdometryConfig&)>& edit) {
    LidarOdometryConfig config = testing::SimulatedLioConfig();
    config.use_camera = true;
    config.camera =
        std::make_shared<PinholeRadtan>(PinholeRadtanIntrinsics{{640, 480, 400, 400, 319.5, 239.5}});
    edit(config);
    const Status status = config.Validate();
    return status.ok() ? std::string("ok") : status.message();
  };
  EXPECT_EQ(message([](LidarOdometryConfig&) {}), "ok");
  EXPECT_NE(message([](LidarOdometryConfig& c) { c.use_imu = false; }).find("lio.use_camera"),
            std::string::npos);
  EXPECT_NE(message([](LidarOdometryConfig& c) { c.camera.reset(); }).find("lio.camera"), std::string::npos);
  EXPECT_NE(
      message([](LidarOdometryConfig& c) { c.visual.max_depth_m = 0.1; }).find("lio.visual.max_depth_m"),
      std::string::npos);
  EXPECT_NE(message([](LidarOdometryConfig& c) {
              c.T_body_camera = SE3(SO3(), Eigen::Vector3d(NAN, 0, 0));
            }).find("lio.T_body_camera"),
            std::string::npos);
}

}  // namespace
}  // namespace uf::estimator
