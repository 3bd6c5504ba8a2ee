#include "odometry/estimator/lidar/plane_fit.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace uf::estimator {

std::optional<Plane> FitPlane(const PointMoments& moments, const Eigen::Vector3d& origin,
                              const PlaneFitGate& gate) {
  if (moments.count < gate.min_points || moments.count < 3) return std::nullopt;
  const double inverse_count = 1.0 / moments.count;
  const Eigen::Vector3d mean = moments.sum * inverse_count;
  const Eigen::Matrix3d covariance = moments.sum_outer * inverse_count - mean * mean.transpose();
  // Closed-form 3x3 solver: eigenvalues ascending, accurate enough for the gate and the normal.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  const Eigen::Vector3d& lambda = solver.eigenvalues();
  const double lambda_min = std::max(lambda(0), 0.0);
  // Degenerate spread: all points on a line (or one spot) define no plane. 1e-8 m^2 = (0.1 mm)^2.
  if (!(lambda(1) > 1e-8)) return std::nullopt;
  if (lambda_min > gate.max_eigen_ratio * lambda(1)) return std::nullopt;
  Plane plane;
  plane.normal = solver.eigenvectors().col(0).normalized();
  plane.point = origin + mean;
  plane.sigma = std::max(std::sqrt(lambda_min), gate.min_sigma_m);
  return plane;
}

}  // namespace uf::estimator
