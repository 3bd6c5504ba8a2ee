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
  if (window_scans < 3) return Bad("window_scans", ">= 3", window_scans);
  if (!Positive(static_max_gyro_std)) return Bad("static_max_gyro_std", "> 0", static_max_gyro_std);
  if (!Positive(static_max_acc_std)) return Bad("static_max_acc_std", "> 0", static_max_acc_std);
  if (!Positive(static_max_motion_m)) return Bad("static_max_motion_m", "> 0", static_max_motion_m);
  if (!Positive(max_gravity_error) || max_gravity_error >= 1)
    return Bad("max_gravity_error", "in (0, 1)", max_gravity_error);
  return {};
}

}  // namespace uf::estimator
