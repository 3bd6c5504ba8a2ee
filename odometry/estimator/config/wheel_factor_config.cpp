#include "odometry/estimator/config/wheel_factor_config.h"

#include <cmath>

#include "odometry/estimator/config/field_rules.h"

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const char* field, const char* rule, T value) {
  return FieldMustBe("lio.wheel", field, rule, value);
}

}  // namespace

Status WheelFactorConfig::Validate() const {
  // Zero densities would make the information infinite (a singular covariance).
  if (!Positive(forward_velocity_density))
    return Bad("forward_velocity_density", "finite and > 0", forward_velocity_density);
  if (!Positive(yaw_rate_density)) return Bad("yaw_rate_density", "finite and > 0", yaw_rate_density);
  if (!Positive(nonholonomic_velocity_density))
    return Bad("nonholonomic_velocity_density", "finite and > 0", nonholonomic_velocity_density);
  if (!(std::isfinite(suspension_tilt_sigma) && suspension_tilt_sigma >= 0))
    return Bad("suspension_tilt_sigma", "finite and >= 0", suspension_tilt_sigma);
  if (!(std::isfinite(tilt_per_acceleration) && tilt_per_acceleration >= 0))
    return Bad("tilt_per_acceleration", "finite and >= 0", tilt_per_acceleration);
  if (!Positive(roll_pitch_rate_density))
    return Bad("roll_pitch_rate_density", "finite and > 0", roll_pitch_rate_density);
  if (!Positive(max_gap_s)) return Bad("max_gap_s", "finite and > 0", max_gap_s);
  if (!(std::abs(time_offset_s) <= 1.0)) return Bad("time_offset_s", "in [-1, 1]", time_offset_s);
  if (!Positive(scale_prior_sigma)) return Bad("scale_prior_sigma", "finite and > 0", scale_prior_sigma);
  const WheelScheduleConfig& w = schedule;
  if (!Positive(w.speed_tolerance_mps))
    return Bad("schedule.speed_tolerance_mps", "finite and > 0", w.speed_tolerance_mps);
  if (!Positive(w.yaw_rate_tolerance_rad_s))
    return Bad("schedule.yaw_rate_tolerance_rad_s", "finite and > 0", w.yaw_rate_tolerance_rad_s);
  if (!(std::isfinite(w.drift_mps_per_s) && w.drift_mps_per_s >= 0))
    return Bad("schedule.drift_mps_per_s", "finite and >= 0", w.drift_mps_per_s);
  if (!Positive(w.max_shut_s)) return Bad("schedule.max_shut_s", "finite and > 0", w.max_shut_s);
  if (!(std::isfinite(w.change_window_s) && w.change_window_s >= 0))
    return Bad("schedule.change_window_s", "finite and >= 0", w.change_window_s);
  if (!Positive(w.change_tolerance_mps))
    return Bad("schedule.change_tolerance_mps", "finite and > 0", w.change_tolerance_mps);
  if (!(std::isfinite(w.baseline_time_s) && w.baseline_time_s >= 0))
    return Bad("schedule.baseline_time_s", "finite and >= 0", w.baseline_time_s);
  if (!(w.speed_weight >= 0 && w.speed_weight <= 1))
    return Bad("schedule.speed_weight", "in [0, 1]", w.speed_weight);
  if (!(w.threshold > 0 && w.threshold < 1)) return Bad("schedule.threshold", "in (0, 1)", w.threshold);
  if (!(w.release_margin >= 0 && w.release_margin < w.threshold))
    return Bad("schedule.release_margin", "in [0, threshold)", w.release_margin);
  if (w.release_keyframes < 1) return Bad("schedule.release_keyframes", ">= 1", w.release_keyframes);
  return {};
}

}  // namespace uf::estimator
