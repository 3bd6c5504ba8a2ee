#include "odometry/estimator/config/inertial_init_config.h"

#include <cmath>
#include <sstream>

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const char* field, const char* rule, T value) {
  std::ostringstream message;
  message << "lio.init." << field << ": must be " << rule << ", got " << value;
  return Status::Error(message.str());
}

bool Positive(double v) { return std::isfinite(v) && v > 0; }

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
