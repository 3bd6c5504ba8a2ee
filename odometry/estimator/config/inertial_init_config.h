// Configuration of the inertial initialization of LIO (inertial_alignment.h): the window it waits for and the
// thresholds of the static and LiDAR-aided modes.
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

struct InertialInitConfig {
  int window_scans = 5;               // LiDAR scans solved as LO before the alignment is tried
  double static_max_gyro_std = 0.02;  // rad/s: spread of the angular rate while static
  double static_max_acc_std = 0.3;    // m/s^2: spread of the specific force while static
  double static_max_motion_m = 0.05;  // the LO poses may move this much while static
  double max_gravity_error = 0.1;     // M: admitted when ||g| - gravity| <= this fraction of gravity

  Status Validate() const;  // names the field and value ("lio.init.<field>: ...")
};

}  // namespace uf::estimator
