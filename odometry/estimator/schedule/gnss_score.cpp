#include "odometry/estimator/schedule/gnss_score.h"

#include <algorithm>
#include <cmath>

namespace uf::estimator {

double FixQuality(GnssFixStatus status) {
  switch (status) {
    case GnssFixStatus::kRtkFixed:
      return 1.0;
    case GnssFixStatus::kRtkFloat:
      return 0.75;
    case GnssFixStatus::kSbas:
      return 0.5;
    case GnssFixStatus::kFix:
      return 0.25;
    case GnssFixStatus::kNoFix:
      break;
  }
  return 0.0;
}

GnssCheck ScoreGnssFix(Stamp stamp, GnssFixStatus status, double covariance_trace_m2, double d2, double gate,
                       bool active) {
  GnssCheck c{.stamp = stamp,
              .fix_quality = FixQuality(status),
              .covariance_trace_m2 = covariance_trace_m2,
              .innovation_d2 = d2,
              .active = active};
  const double innovation = std::isfinite(d2) && gate > 0 ? std::min(1.0, d2 / gate) : 1.0;
  const double spread = std::isfinite(covariance_trace_m2)
                            ? std::min(1.0, covariance_trace_m2 / kGnssCovarianceTraceScale_m2)
                            : 1.0;
  c.score = ((1.0 - c.fix_quality) + spread + innovation) / 3.0;
  return c;
}

}  // namespace uf::estimator
