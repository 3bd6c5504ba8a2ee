// The GNSS fix's score of the reliability scheduling (docs/METHOD.md "Factor-wise reliability scheduling";
// paper Sec. III-D, GNSS integrity checks), the paper's sum with equal weights:
//   D = (1 - q_fix) / 3 + min(1, tr(Sigma) / tau_Sigma) / 3 + min(1, d^2 / tau_nu) / 3,
// q_fix from the fix's status (RTK fixed 1, RTK float 0.75, SBAS 0.5, single 0.25, none 0), tau_Sigma
// 10 m^2 (a single-point fix's 1.5 m / 3 m sigmas give 13.5 m^2; RTK fixed's centimetres ~0) and tau_nu
// the innovation test's gate. The factor's admission is the innovation test's (gnss/integrity_check.h),
// which the score does not change.
#pragma once

#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"

namespace uf::estimator {

inline constexpr double kGnssCovarianceTraceScale_m2 = 10.0;  // tau_Sigma

double FixQuality(GnssFixStatus status);

// A non-finite d2 (no prediction) scores its term 1.
GnssCheck ScoreGnssFix(Stamp stamp, GnssFixStatus status, double covariance_trace_m2, double d2, double gate,
                       bool active);

}  // namespace uf::estimator
