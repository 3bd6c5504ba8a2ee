#include "odometry/estimator/gnss/integrity_check.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <numbers>

namespace uf::estimator {

double ChiSquareTail(double x, int dof) {
  const double half = 0.5 * x;
  if (dof == 1) return std::erfc(std::sqrt(half));
  if (dof == 2) return std::exp(-half);
  return std::erfc(std::sqrt(half)) + std::sqrt(2.0 * x / std::numbers::pi) * std::exp(-half);
}

double ChiSquareQuantile(double tail, int dof) {
  // The tail falls monotonically in x: bisection to far below any gate's precision.
  double low = 0.0, high = 1e4;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (low + high);
    (ChiSquareTail(mid, dof) > tail ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

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
  // d^2 = |C^-1 e|^2 with S = C C^T; the first two components of w = C^-1 e whiten the horizontal part.
  const Eigen::Vector3d w = llt.matrixL().solve(result.innovation);
  result.d2 = w.squaredNorm();
  result.d2_horizontal = w.head<2>().squaredNorm();
  result.d2_vertical = w.z() * w.z();
  const double tail = ChiSquareTail(config.integrity_gate, 3);
  result.horizontal_accepted = result.d2_horizontal <= ChiSquareQuantile(tail, 2);
  result.accepted = result.horizontal_accepted && result.d2 <= config.integrity_gate &&
                    result.d2_vertical <= ChiSquareQuantile(tail, 1);
  return result;
}

}  // namespace uf::estimator
