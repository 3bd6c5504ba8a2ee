// Everything `ultrafusion sim` needs to generate a sequence: scene, trajectory, the sensors with their
// models, placements on the body and the errors to inject into the calibration the user is given. Plain
// structs with the defaults documented here; viewer/app maps the YAML `sim:` section and the command-line
// options onto them.
//
// Frames: the body frame is the IMU frame (x forward, y left, z up); the world is east-north-up at the
// scene's geodetic origin. Time: the sequence starts at start_stamp (true time, the IMU's clock).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "odometry/sim/gnss_model.h"
#include "odometry/sim/imu_model.h"
#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/sensors/camera_renderer.h"
#include "odometry/sim/sensors/lidar_model.h"
#include "odometry/sim/wheel_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::sim {

// Where a sensor sits and what the user is told about it.
struct SensorPlacement {
  SE3 T_body_sensor;  // the true extrinsic
  // The sensor stamps its data this late: stamp = true time + stamp_delay_s. The calibration files state
  // time_offset_s = -stamp_delay_s in calibration_true.yaml and 0 in calibration.yaml.
  double stamp_delay_s = 0.0;
  // The extrinsic written to calibration.yaml (and dataset.yaml) is T_body_sensor * Exp([t_err; r_err]):
  // a rotation error (rotation vector, degrees, sensor frame) and a translation error (m, sensor frame).
  Eigen::Vector3d rotation_error_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d translation_error_m = Eigen::Vector3d::Zero();

  // The extrinsic the user is given.
  SE3 GivenExtrinsic() const;
};

// A camera at `translation` in the body frame looking forward: its optical axis (z) along body x, its x
// axis along -body y (right), its y axis along -body z (down).
SE3 ForwardLookingCamera(const Eigen::Vector3d& translation);

struct SimulatedImuConfig {
  bool enabled = true;
  double rate_hz = 200.0;
  // Densities of EuRoC's ADIS16448 (its sensor.yaml): a good MEMS IMU. Biases start at zero.
  ImuNoise noise = {2.0e-3, 1.6968e-4, 3.0e-3, 1.9393e-5, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                    0.0,    0.0};
};

struct SimulatedLidarConfig {
  bool enabled = true;
  LidarConfig model;  // spinning32 at 10 Hz by default
  // Scans written per second, in [0, model.rate_hz]; 0: every sweep. Sweeps keep their duration
  // 1 / model.rate_hz; only sweep j = round(k * model.rate_hz / keyframe_rate_hz), k = 0, 1, ..., is cast
  // and written (every 5th at 10 and 2 Hz; unevenly spaced when the ratio is no whole number).
  double keyframe_rate_hz = 0.0;
  SensorPlacement placement = {SE3(SO3(), Eigen::Vector3d(0.0, 0.0, 0.25))};
};

struct SimulatedCameraConfig {
  bool enabled = true;
  CameraConfig model;  // 640x480 at 10 Hz by default
  SensorPlacement placement = {ForwardLookingCamera(Eigen::Vector3d(0.3, 0.0, 0.1))};
  // > 0: a stereo rig, a second camera (cam1, RightCameraPlacement) this far to the right of cam0, m.
  double stereo_baseline_m = 0.0;
};

// The second camera of a stereo rig: cam0's model, timing and placement moved stereo_baseline_m along
// cam0's x axis (its right). The rig is given as one body: the right camera's given extrinsic is cam0's
// given one moved by the same baseline, so the pair's relative extrinsic is always exact.
SensorPlacement RightCameraPlacement(const SimulatedCameraConfig& camera);

struct SimulatedWheelConfig {
  bool enabled = true;
  WheelConfig model;  // 50 Hz
  // The vehicle base frame (x forward, z up) between the wheels, below and behind the IMU.
  SensorPlacement placement = {SE3(SO3(), Eigen::Vector3d(-0.3, 0.0, -0.5))};
};

struct SimulatedGnssConfig {
  bool enabled = true;
  GnssConfig model;  // 5 Hz single-point fixes by default
  SensorPlacement placement = {SE3(SO3(), Eigen::Vector3d(0.0, 0.0, 0.4))};  // antenna lever arm
};

struct TrajectorySource {
  std::string file;             // TUM or KITTI pose file; empty: the scene's default trajectory
  std::string format = "auto";  // auto | tum | kitti | euroc
  double kitti_rate_hz = 10.0;  // KITTI pose files have no stamps: poses are this far apart
  // Spline resampling of the poses (continuous acceleration). The handheld motion uses at most
  // kHandheldKnotSpacingS: its bounce has a ~4 Hz harmonic that 0.1 s knots smooth away.
  double knot_spacing_s = 0.1;
  // How the body moves along the scene's default path (no file): kVehicle (default_trajectory.h) or
  // kHandheld (handheld_trajectory.h). A trajectory file brings its own motion: kHandheld is an error there.
  Motion motion = Motion::kVehicle;
};

inline constexpr double kHandheldKnotSpacingS = 0.02;
inline constexpr double kHandheldBodyHeightM = 1.4;  // the command line's --motion handheld sets it

struct SimulationConfig {
  std::string scene = "urban";
  std::uint64_t seed = 1;
  double duration_s = 60.0;  // a trajectory file: at most this much of it (<= 0: all of it)
  Stamp start_stamp = 1'700'000'000'000'000'000;  // 2023-11-14 22:13:20 UTC; a file's own stamps win
  TrajectorySource trajectory;
  double body_height_m = 1.8;  // body (IMU) frame above the ground
  double ground_truth_rate_hz = 200.0;
  GeodeticOrigin origin = {49.0069, 8.4037, 115.0};  // world origin on the WGS84 ellipsoid
  int threads = 0;  // ray-casting threads; 0: all cores. The output does not depend on it.
  bool write_bag = false;

  SimulatedImuConfig imu;
  SimulatedLidarConfig lidar;
  SimulatedCameraConfig camera;
  SimulatedWheelConfig wheel;
  SimulatedGnssConfig gnss;
};

// Checks every value (ranges, finiteness, the scene name, a sensor at least) before anything runs; the
// message names the field as the config file spells it ("sim.lidar.rate_hz: must be in (0, 100], got -5").
Status ValidateSimulationConfig(const SimulationConfig& config);

}  // namespace uf::sim
