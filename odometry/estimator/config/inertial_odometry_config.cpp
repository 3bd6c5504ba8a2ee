#include "odometry/estimator/config/inertial_odometry_config.h"

#include <string>

#include "odometry/estimator/config/field_rules.h"

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const char* field, const char* rule, T value) {
  return FieldMustBe("wio", field, rule, value);
}

// The nested configs name their fields as in the LIO section ("lio.wheel.max_gap_s"): the same fields under
// "wio." here.
Status UnderWio(const Status& status) {
  if (status.ok()) return status;
  const std::string& message = status.message();
  if (message.rfind("lio.", 0) == 0) return Status::Error("wio." + message.substr(4));
  return Status::Error("wio." + message);
}

}  // namespace

Status InertialOdometryConfig::Validate() const {
  if (!Positive(node_interval_s)) return Bad("node_interval_s", "> 0", node_interval_s);
  if (init_window_nodes < 3) return Bad("init_window_nodes", ">= 3", init_window_nodes);
  if (window_size < init_window_nodes)
    return Bad("window_size", (">= init_window_nodes (" + std::to_string(init_window_nodes) + ")").c_str(),
               window_size);
  if (max_iterations < 1) return Bad("max_iterations", ">= 1", max_iterations);
  if (!Positive(max_solver_time_s)) return Bad("max_solver_time_s", "> 0", max_solver_time_s);
  if (Status s = marginalization.Validate(); !s.ok()) return UnderWio(s);
  if (Status s = ValidateImuNoiseParams(imu); !s.ok()) return UnderWio(s);
  if (Status s = init.Validate(); !s.ok()) return UnderWio(s);
  if (!Positive(init_accel_bias_sigma)) return Bad("init_accel_bias_sigma", "> 0", init_accel_bias_sigma);
  if (!Positive(init_gyro_bias_sigma)) return Bad("init_gyro_bias_sigma", "> 0", init_gyro_bias_sigma);
  if (!Positive(imu_max_gap_s)) return Bad("imu_max_gap_s", "> 0", imu_max_gap_s);
  if (!Positive(max_speed_mps)) return Bad("max_speed_mps", "> 0", max_speed_mps);
  if (Status s = wheel.Validate(); !s.ok()) return UnderWio(s);
  if (!T_body_wheel.matrix().allFinite()) return Bad("T_body_wheel", "finite", "non-finite");
  if (!Positive(wheel_max_wait_s)) return Bad("wheel_max_wait_s", "> 0", wheel_max_wait_s);
  if (!use_wheel && !use_camera) return Bad("use_wheel", "true without the camera", "false");
  if (use_camera) {
    if (Status s = visual.Validate(); !s.ok()) return UnderWio(s);
    if (!camera) return Bad("camera", "a camera model with use_camera", "none");
    if (!T_body_camera.matrix().allFinite()) return Bad("T_body_camera", "finite", "non-finite");
  }
  if (!use_gnss) return {};
  if (Status s = gnss.Validate(); !s.ok()) return UnderWio(s);
  if (!T_body_gnss.matrix().allFinite()) return Bad("T_body_gnss", "finite", "non-finite");
  return {};
}

}  // namespace uf::estimator
