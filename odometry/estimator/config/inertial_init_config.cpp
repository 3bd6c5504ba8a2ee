#include "odometry/estimator/config/inertial_init_config.h"

#include "odometry/estimator/config/field_rules.h"

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const char* field, const char* rule, T value) {
  return FieldMustBe("lio.init", field, rule, value);
}

}  // namespace

Status InertialInitConfig::Validate() const {
  if (min_scans < 3) return Bad("min_scans", ">= 3", min_scans);
  if (map_settle_scans < 0 || map_settle_scans > 20)
    return Bad("map_settle_scans", "in [0, 20]", map_settle_scans);
  if (max_scans < min_scans || max_scans > 200) return Bad("max_scans", "in [min_scans, 200]", max_scans);
  if (!Positive(static_min_duration_s)) return Bad("static_min_duration_s", "> 0", static_min_duration_s);
  if (!Positive(static_max_gyro_std)) return Bad("static_max_gyro_std", "> 0", static_max_gyro_std);
  if (!Positive(static_max_vibration_deg))
    return Bad("static_max_vibration_deg", "> 0", static_max_vibration_deg);
  if (!Positive(static_max_acc_std)) return Bad("static_max_acc_std", "> 0", static_max_acc_std);
  if (!Positive(static_max_speed_mps)) return Bad("static_max_speed_mps", "> 0", static_max_speed_mps);
  if (!Positive(max_gravity_error) || max_gravity_error >= 1)
    return Bad("max_gravity_error", "in (0, 1)", max_gravity_error);
  if (!Positive(max_tilt_sigma_deg) || max_tilt_sigma_deg > 45)
    return Bad("max_tilt_sigma_deg", "in (0, 45]", max_tilt_sigma_deg);
  if (!Positive(lidar_position_sigma_m)) return Bad("lidar_position_sigma_m", "> 0", lidar_position_sigma_m);
  if (!Positive(accel_bias_sigma)) return Bad("accel_bias_sigma", "> 0", accel_bias_sigma);
  if (!Positive(max_chi2_per_dof)) return Bad("max_chi2_per_dof", "> 0", max_chi2_per_dof);
  return {};
}

}  // namespace uf::estimator
