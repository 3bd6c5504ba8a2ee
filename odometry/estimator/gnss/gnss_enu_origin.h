// The ENU frame in which the GNSS factors work: placed at the first fix that passed ScreenFix (its
// latitude, longitude and ellipsoidal height), then fixed for the run, so that every later fix converts
// exactly (through ECEF, odometry/types/geodetic.h) and stays near the origin in metres.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "odometry/types/geodetic.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf::estimator {

class GnssEnuOrigin {
 public:
  // The fix's position in the ENU frame (m). The first call places the origin at `fix`, which must have
  // passed ScreenFix; fails only for a position no origin can be placed at (never for a screened fix).
  Expected<Eigen::Vector3d> ToEnu(const GnssFix& fix);

  bool has_origin() const { return frame_.has_value(); }
  // The frame, once placed.
  const std::optional<EnuFrame>& frame() const { return frame_; }

 private:
  std::optional<EnuFrame> frame_;
};

// (latitude deg, longitude deg, ellipsoidal height m) of a fix.
inline Eigen::Vector3d FixGeodetic(const GnssFix& fix) {
  return Eigen::Vector3d(fix.latitude_deg, fix.longitude_deg, fix.altitude_m);
}

}  // namespace uf::estimator
