#include "odometry/estimator/gnss/integrity_check.h"

#include <Eigen/Cholesky>
#include <limits>

namespace uf::estimator {

IntegrityResult CheckIntegrity(const Eigen::Vector3d& antenna_world_predicted, const EnuAlignment& alignment,
                               const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& fix_covariance,
                               double distance_m, const GnssFactorConfig& config) {
  IntegrityResult result;
  result.innovation = alignment.Apply(antenna_world_predicted) - fix_enu;
  const double drift_m = config.prediction_drift_fraction * distance_m;
  const double prediction_variance =
      config.prediction_sigma_m * config.prediction_sigma_m + drift_m * drift_m;
  const Eigen::Matrix3d S = fix_covariance + prediction_variance * Eigen::Matrix3d::Identity();
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  if (!result.innovation.allFinite() || !S.allFinite() || llt.info() != Eigen::Success) {
    result.d2 = std::numeric_limits<double>::infinity();
    return result;
  }
  // d^2 = |C^-1 e|^2 with S = C C^T.
  result.d2 = llt.matrixL().solve(result.innovation).squaredNorm();
  result.accepted = result.d2 <= config.integrity_gate;
  return result;
}

}  // namespace uf::estimator
