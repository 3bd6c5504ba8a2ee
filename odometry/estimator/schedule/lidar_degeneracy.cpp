#include "odometry/estimator/schedule/lidar_degeneracy.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace uf::estimator {
namespace {

// lambda_min / (trace / 3) of a symmetric positive semi-definite 3x3 block, and its weakest direction.
double Isotropy(const Eigen::Matrix3d& block, Eigen::Vector3d* weakest = nullptr) {
  const double trace = block.trace();
  if (!(trace > 0) || !std::isfinite(trace)) return 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(block);
  if (weakest) *weakest = eigen.eigenvectors().col(0);  // eigenvalues ascending
  return std::clamp(eigen.eigenvalues()(0) / (trace / 3.0), 0.0, 1.0);
}

}  // namespace

LidarDegeneracy AnalyzeLidarInformation(const Matrix6d& information, int matches) {
  LidarDegeneracy d;
  d.matches = matches;
  if (matches < 6 || !information.allFinite()) return d;
  d.translation_isotropy = Isotropy(information.topLeftCorner<3, 3>(), &d.weak_translation);
  d.rotation_isotropy = Isotropy(information.bottomRightCorner<3, 3>());
  const double worst = std::min(d.translation_isotropy, d.rotation_isotropy);
  d.score = 1.0 - std::min(1.0, worst / kHealthyIsotropy);
  return d;
}

Matrix6d WeakDirectionProjector(const Matrix6d& information) {
  Matrix6d P = Matrix6d::Identity();
  if (!information.allFinite()) return P;
  for (int block = 0; block < 2; ++block) {
    const Eigen::Matrix3d H = information.block<3, 3>(3 * block, 3 * block);
    const double mean = H.trace() / 3.0;
    if (!(mean > 0)) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(H);
    for (int i = 0; i < 3; ++i) {
      if (eigen.eigenvalues()(i) >= kHealthyIsotropy * mean) continue;
      const Eigen::Vector3d v = eigen.eigenvectors().col(i);
      P.block<3, 3>(3 * block, 3 * block) -= v * v.transpose();
    }
  }
  return P;
}

}  // namespace uf::estimator
