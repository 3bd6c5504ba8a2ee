#include "odometry/eval/alignment.h"

#include <Eigen/SVD>
#include <cassert>
#include <string>

namespace uf {

Expected<Similarity> Umeyama(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  assert(source.size() == target.size());
  const std::size_t count = source.size();
  if (count < 3)
    return Status::Error("alignment needs at least 3 matched pairs, got " + std::to_string(count));
  const double n = static_cast<double>(count);

  Eigen::Vector3d mean_source = Eigen::Vector3d::Zero(), mean_target = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    mean_source += source[i];
    mean_target += target[i];
  }
  mean_source /= n;
  mean_target /= n;

  // sigma_x^2 = 1/n sum |x_i - mean_x|^2, Sigma_xy = 1/n sum (y_i - mean_y)(x_i - mean_x)^T
  double variance_source = 0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d x = source[i] - mean_source;
    variance_source += x.squaredNorm();
    covariance += (target[i] - mean_target) * x.transpose();
  }
  variance_source /= n;
  covariance /= n;

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  // Rank below 2 means the points lie on a line (or coincide): rotation about that line is unobservable.
  // evo tests d > machine epsilon in absolute terms; a relative test also catches lines that are noisy at the
  // rounding level.
  if (!(d[1] > 1e-12 * d[0]) || !(variance_source > 0))
    return Status::Error("degenerate alignment: the " + std::to_string(count) +
                         " matched positions are collinear or coincide, so the rotation is undetermined "
                         "(use --align none)");

  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;  // reflection guard
  Similarity result;
  result.rotation = SO3(Eigen::Matrix3d(svd.matrixU() * S * svd.matrixV().transpose()));
  result.scale = with_scale ? (d.asDiagonal() * S).trace() / variance_source : 1.0;
  result.translation = mean_target - result.scale * (result.rotation.matrix() * mean_source);
  return result;
}

}  // namespace uf
