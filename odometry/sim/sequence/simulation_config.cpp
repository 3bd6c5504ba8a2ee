#include "odometry/sim/sequence/simulation_config.h"

#include <cmath>
#include <sstream>

#include "odometry/sim/scene/scene_builder.h"

namespace uf::sim {
namespace {

constexpr double kDegree = M_PI / 180.0;

std::string Text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

Status Range(const std::string& field, double value, double low, double high, const char* interval) {
  if (std::isfinite(value) && value > low && value <= high) return {};
  return Status::Error("sim." + field + ": must be in " + interval + ", got " + Text(value));
}

Status NonNegative(const std::string& field, double value) {
  if (std::isfinite(value) && value >= 0.0) return {};
  return Status::Error("sim." + field + ": must be finite and >= 0, got " + Text(value));
}

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// The models name their fields "lidar.rate_hz"; in the config file they sit under "sim.".
Status InSim(Status status) {
  if (status.ok()) return status;
  return Status::Error("sim." + status.message());
}

Status ValidatePlacement(const std::string& sensor, const SensorPlacement& placement) {
  if (!placement.T_body_sensor.matrix().allFinite())
    return Status::Error("sim." + sensor + ".extrinsic: not finite");
  if (!std::isfinite(placement.stamp_delay_s) || std::abs(placement.stamp_delay_s) > 10.0)
    return Status::Error("sim." + sensor + ".stamp_delay_s: must be within +-10 s, got " +
                         Text(placement.stamp_delay_s));
  if (!Finite(placement.rotation_error_deg) || placement.rotation_error_deg.norm() >= 180.0)
    return Status::Error("sim." + sensor + ".extrinsic_error.rotation_deg: must be finite with norm < 180");
  if (!Finite(placement.translation_error_m))
    return Status::Error("sim." + sensor + ".extrinsic_error.translation_m: not finite");
  return {};
}

Status ValidateImu(const SimulatedImuConfig& imu) {
  if (Status s = Range("imu.rate_hz", imu.rate_hz, 0.0, 10000.0, "(0, 10000]"); !s.ok()) return s;
  const ImuNoise& n = imu.noise;
  for (const auto& [field, value] : {std::pair{"accel_noise_density", n.accel_noise_density},
                                     {"gyro_noise_density", n.gyro_noise_density},
                                     {"accel_bias_random_walk", n.accel_bias_random_walk},
                                     {"gyro_bias_random_walk", n.gyro_bias_random_walk},
                                     {"accel_saturation", n.accel_saturation},
                                     {"gyro_saturation", n.gyro_saturation}}) {
    if (Status s = NonNegative(std::string("imu.") + field, value); !s.ok()) return s;
  }
  if (!Finite(n.initial_accel_bias)) return Status::Error("sim.imu.initial_accel_bias: not finite");
  if (!Finite(n.initial_gyro_bias)) return Status::Error("sim.imu.initial_gyro_bias: not finite");
  return {};
}

}  // namespace

SE3 ForwardLookingCamera(const Eigen::Vector3d& translation) {
  Eigen::Matrix3d R_body_camera;
  R_body_camera << 0, 0, 1,  //
      -1, 0, 0,              //
      0, -1, 0;
  return SE3(SO3(R_body_camera), translation);
}

// With B = the baseline translation (b, 0, 0): T_body_right = T_body_cam0 B, and the given one
// T_body_cam0 Exp(e) B = T_body_right Exp(e_right) for Exp(e_right) = B^-1 Exp(e) B.
SensorPlacement RightCameraPlacement(const SimulatedCameraConfig& camera) {
  const SE3 baseline(SO3(), Eigen::Vector3d(camera.stereo_baseline_m, 0.0, 0.0));
  const SensorPlacement& left = camera.placement;
  Vector6d error;
  error << left.translation_error_m, left.rotation_error_deg * kDegree;
  const Vector6d right_error = (baseline.inverse() * SE3::Exp(error) * baseline).Log();
  SensorPlacement right = left;
  right.T_body_sensor = left.T_body_sensor * baseline;
  right.translation_error_m = right_error.head<3>();
  right.rotation_error_deg = right_error.tail<3>() / kDegree;
  return right;
}

SE3 SensorPlacement::GivenExtrinsic() const {
  Vector6d error;
  error << translation_error_m, rotation_error_deg * kDegree;
  return T_body_sensor * SE3::Exp(error);
}

Status ValidateSimulationConfig(const SimulationConfig& config) {
  bool known_scene = false;
  std::string names;
  for (std::string_view name : SceneNames()) {
    known_scene |= name == config.scene;
    names += (names.empty() ? "" : ", ") + std::string(name);
  }
  if (!known_scene) return Status::Error("sim.scene: unknown scene '" + config.scene + "' (" + names + ")");
  if (config.trajectory.file.empty()) {
    if (Status s = Range("duration_s", config.duration_s, 0.0, 3600.0, "(0, 3600]"); !s.ok()) return s;
  } else if (!std::isfinite(config.duration_s)) {  // with a file, <= 0 means all of it
    return Status::Error("sim.duration_s: not finite");
  }
  if (config.start_stamp < 0) return Status::Error("sim.start_time_s: must be >= 0 (ROS time is unsigned)");
  if (Status s = Range("trajectory.kitti_rate_hz", config.trajectory.kitti_rate_hz, 0.0, 1000.0, "(0, 1000]");
      !s.ok())
    return s;
  if (Status s =
          Range("trajectory.knot_spacing_s", config.trajectory.knot_spacing_s, 0.001, 10.0, "(0.001, 10]");
      !s.ok())
    return s;
  if (config.trajectory.motion != Motion::kVehicle && !config.trajectory.file.empty())
    return Status::Error("sim.trajectory.motion: " + std::string(MotionName(config.trajectory.motion)) +
                         " moves along the scene's default path; the trajectory file '" +
                         config.trajectory.file + "' brings its own motion (use vehicle)");
  if (Status s = Range("body_height_m", config.body_height_m, -1e-12, 100.0, "[0, 100]"); !s.ok()) return s;
  if (Status s = Range("ground_truth_rate_hz", config.ground_truth_rate_hz, 0.0, 10000.0, "(0, 10000]");
      !s.ok())
    return s;
  if (Status s = InSim(ValidateGeodeticOrigin(config.origin)); !s.ok()) return s;
  if (config.threads < 0)
    return Status::Error("sim.threads: must be >= 0, got " + std::to_string(config.threads));
  if (!config.imu.enabled && !config.lidar.enabled && !config.camera.enabled && !config.wheel.enabled &&
      !config.gnss.enabled)
    return Status::Error("sim: every sensor is disabled; enable at least one");

  if (config.imu.enabled)
    if (Status s = ValidateImu(config.imu); !s.ok()) return s;
  if (config.lidar.enabled) {
    if (Status s = InSim(ValidateLidarConfig(config.lidar.model)); !s.ok()) return s;
    const double keyframe_rate = config.lidar.keyframe_rate_hz;
    if (!(std::isfinite(keyframe_rate) && keyframe_rate >= 0.0 &&
          keyframe_rate <= config.lidar.model.rate_hz))
      return Status::Error("sim.lidar.keyframe_rate_hz: must be in [0, sim.lidar.rate_hz = " +
                           Text(config.lidar.model.rate_hz) + "] (0: every sweep), got " +
                           Text(keyframe_rate));
    if (Status s = ValidatePlacement("lidar", config.lidar.placement); !s.ok()) return s;
  }
  if (config.camera.enabled) {
    if (Status s = InSim(ValidateCameraConfig(config.camera.model)); !s.ok()) return s;
    if (Status s = ValidatePlacement("camera", config.camera.placement); !s.ok()) return s;
    const double baseline = config.camera.stereo_baseline_m;
    if (!(std::isfinite(baseline) && baseline >= 0.0 && baseline <= 10.0))
      return Status::Error("sim.camera.stereo_baseline_m: must be in [0, 10] m (0: no second camera), got " +
                           Text(baseline));
  }
  if (config.wheel.enabled) {
    if (Status s = InSim(config.wheel.model.Validate()); !s.ok()) return s;
    if (Status s = ValidatePlacement("wheel", config.wheel.placement); !s.ok()) return s;
  }
  if (config.gnss.enabled) {
    if (Status s = InSim(config.gnss.model.Validate()); !s.ok()) return s;
    if (Status s = ValidatePlacement("gnss", config.gnss.placement); !s.ok()) return s;
  }
  return {};
}

}  // namespace uf::sim
