#include "odometry/estimator/config/lidar_odometry_config.h"

#include <cmath>
#include <string>

#include "odometry/estimator/config/field_rules.h"

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const char* field, const char* rule, T value, const char* section = "lo") {
  return FieldMustBe(section, field, rule, value);
}

}  // namespace

Status LidarOdometryConfig::Validate() const {
  if (!Positive(input_voxel_m)) return Bad("input_voxel_m", "> 0", input_voxel_m);
  if (Status s = map.Validate(); !s.ok()) return Status::Error("lo.map: " + s.message());
  if (window_size < 2) return Bad("window_size", ">= 2", window_size);
  if (max_iterations < 1) return Bad("max_iterations", ">= 1", max_iterations);
  if (condensed_lidar_rounds < 0) return Bad("condensed_lidar_rounds", ">= 0", condensed_lidar_rounds);
  if (!Positive(max_solver_time_s)) return Bad("max_solver_time_s", "> 0", max_solver_time_s);
  if (max_residuals_per_scan < 6) return Bad("max_residuals_per_scan", ">= 6", max_residuals_per_scan);
  if (!Positive(huber_m)) return Bad("huber_m", "> 0", huber_m);
  if (!std::isfinite(min_range_m) || min_range_m < 0) return Bad("min_range_m", ">= 0", min_range_m);
  if (!std::isfinite(max_range_m) || max_range_m <= min_range_m)
    return Bad("max_range_m", "finite and > min_range_m", max_range_m);
  if (!T_body_lidar.matrix().allFinite()) return Bad("T_body_lidar", "finite", "non-finite");
  if (!Positive(map_insert_voxel_m)) return Bad("map_insert_voxel_m", "> 0", map_insert_voxel_m);
  if (association_rounds < 1) return Bad("association_rounds", ">= 1", association_rounds);
  if (!Positive(motion.acc_density)) return Bad("motion.acc_density", "> 0", motion.acc_density);
  if (!Positive(motion.angular_acc_density))
    return Bad("motion.angular_acc_density", "> 0", motion.angular_acc_density);
  if (!std::isfinite(motion.sweep_acc_density) || motion.sweep_acc_density < 0)
    return Bad("motion.sweep_acc_density", ">= 0", motion.sweep_acc_density);
  if (!Positive(max_plane_distance_m)) return Bad("max_plane_distance_m", "> 0", max_plane_distance_m);
  if (!std::isfinite(min_match_ratio) || min_match_ratio < 0 || min_match_ratio > 1)
    return Bad("min_match_ratio", "in [0, 1]", min_match_ratio);
  if (!Positive(max_speed_mps)) return Bad("max_speed_mps", "> 0", max_speed_mps);
  if (!Positive(max_angular_rate_rad_s)) return Bad("max_angular_rate_rad_s", "> 0", max_angular_rate_rad_s);
  if (max_rejected_scans < 1) return Bad("max_rejected_scans", ">= 1", max_rejected_scans);
  if (!Positive(max_prediction_s)) return Bad("max_prediction_s", "> 0", max_prediction_s);
  if (min_points < 6) return Bad("min_points", ">= 6", min_points);
  if (Status s = marginalization.Validate(); !s.ok()) return Status::Error("lo." + s.message());
  if (use_wheel)
    if (Status s = wheel.Validate(); !s.ok()) return s;
  if (use_gnss) {
    if (!use_imu)
      return Status::Error("lio.use_gnss: the GNSS factor needs the IMU (a gravity-aligned world), got LO");
    if (Status s = gnss.Validate(); !s.ok()) return s;
    if (!T_body_gnss.matrix().allFinite()) return Bad("T_body_gnss", "finite", "non-finite", "lio");
  }
  if (use_camera) {
    if (!use_imu) return Status::Error("lio.use_camera: the camera factors need the IMU (LVIO), got LO");
    if (Status s = visual.Validate(); !s.ok()) return Status::Error("lio." + s.message());
    if (!camera) return Bad("camera", "a camera model with use_camera", "none", "lio");
    if (!T_body_camera.matrix().allFinite()) return Bad("T_body_camera", "finite", "non-finite", "lio");
  }
  if (!use_imu) return {};
  if (Status s = ValidateImuNoiseParams(imu); !s.ok()) return Status::Error("lio." + s.message());
  if (Status s = init.Validate(); !s.ok()) return s;
  if (init.min_scans >= window_size)
    return Status::Error("lio.init.min_scans: must be < lo.window_size (" + std::to_string(window_size) +
                         "), got " + std::to_string(init.min_scans));
  if (!Positive(imu_max_gap_s)) return Bad("imu_max_gap_s", "> 0", imu_max_gap_s, "lio");
  if (!Positive(imu_max_wait_s)) return Bad("imu_max_wait_s", "> 0", imu_max_wait_s, "lio");
  if (estimate_lidar_translation && !imu_deskew)
    return Status::Error(
        "lio.estimate_lidar_translation: needs lio.imu_deskew (without it the sweeps' unmodelled motion "
        "pulls the translation 0.3-0.4 m away), got imu_deskew false");
  if (!Positive(lidar_translation_sigma_m))
    return Bad("lidar_translation_sigma_m", "> 0", lidar_translation_sigma_m, "lio");
  if (!Positive(lidar_translation_min_turn_deg))
    return Bad("lidar_translation_min_turn_deg", "> 0", lidar_translation_min_turn_deg, "lio");
  return {};
}

}  // namespace uf::estimator
