#include "odometry/estimator/schedule/imu_score.h"

#include <algorithm>
#include <cmath>

namespace uf::estimator {
namespace {

// min(1, value / scale); a non-finite value saturates.
double Saturating(double value, double scale) {
  return std::isfinite(value) ? std::min(1.0, std::max(0.0, value) / scale) : 1.0;
}

}  // namespace

ImuReliability ScoreImuInterval(const ImuScoreInputs& inputs) {
  ImuReliability r;
  const bool finite = std::isfinite(inputs.rate_rad_s) && std::isfinite(inputs.acceleration_mps2);
  r.excitation = finite ? std::max(Saturating(inputs.rate_rad_s, kImuRateExcitation_rad_s),
                                   Saturating(inputs.acceleration_mps2, kImuAccelExcitation_mps2))
                        : 0.0;
  r.preintegration_chi2 = inputs.chi2;
  r.clipped_steps = inputs.clipped_steps;
  r.score = kImuExcitationWeight * (1.0 - r.excitation) +
            kImuResidualWeight * Saturating(inputs.chi2, kImuChi2Threshold) +
            kImuClippedWeight * (inputs.clipped_steps > 0 ? 1.0 : 0.0);
  return r;
}

}  // namespace uf::estimator
