// Which GNSS fixes the estimator uses, and the covariance each one gets (gnss_factor_config.h).
//
// ScreenFix rejects, with the reason:
//   - a status below GnssFactorConfig::min_status (kNoFix always);
//   - a non-finite latitude, longitude or altitude, a latitude outside [-90, 90], a longitude outside
//     [-180, 180], an altitude outside [-12 km, 100 km] (the ranges of ValidateGeodeticOrigin);
//   - a covariance that is not finite, not symmetric (relative 1e-9) or not positive semidefinite (an
//     eigenvalue below -1e-12 of the largest magnitude, or below -1e-12 m^2);
//   - an all-zero covariance (ROS' COVARIANCE_TYPE_UNKNOWN: the receiver says nothing of its accuracy),
//     unless use_nominal_for_unknown is set. Such a fix is then accepted with the status' nominal sigmas.
//     The default rejects it: an unknown accuracy would be a guess weighted as a measurement.
// A singular but positive semidefinite covariance (say a zero vertical variance) is accepted: the floor
// below makes it definite.
//
// FixCovariance gives the factor's covariance of an accepted fix:
//   S = (C + C^T) / 2           (C reported; diag(h^2, h^2, v^2) nominal when C = 0 and allowed)
//   S = k^2 S                    (k = sigma_scale of the status)
//   S = V max(Lambda, s^2) V^T   (eigenvalues floored at s = min_sigma_m of the status)
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/types/measurements.h"

namespace uf::estimator {

// Why the fix is not used, or nothing when it is.
std::optional<std::string> ScreenFix(const GnssFix& fix, const GnssFactorConfig& config);

// The covariance (m^2, ENU, positive definite) of a fix that passed ScreenFix (asserted in debug builds).
Eigen::Matrix3d FixCovariance(const GnssFix& fix, const GnssFactorConfig& config);

// Whether the fix reports an all-zero covariance (unknown accuracy).
bool HasUnknownCovariance(const GnssFix& fix);

}  // namespace uf::estimator
