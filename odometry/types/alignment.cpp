#include "odometry/types/alignment.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cassert>
#include <cmath>
#include <string>

namespace uf {
namespace {

// Weighted centroids and H = sum_i w_i (target_i - m_t)(source_i - m_s)^T; no weights: all 1.
struct Correlation {
  Eigen::Vector3d mean_source = Eigen::Vector3d::Zero(), mean_target = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
};

Correlation Correlate(std::span<const Eigen::Vector3d> source, std::span<const Eigen::Vector3d> target,
                      std::span<const double> weights) {
  assert(source.size() == target.size() && (weights.empty() || weights.size() == source.size()));
  const auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  Correlation c;
  double total = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    total += weight(i);
    c.mean_source += weight(i) * source[i];
    c.mean_target += weight(i) * target[i];
  }
  c.mean_source /= total;
  c.mean_target /= total;
  for (std::size_t i = 0; i < source.size(); ++i)
    c.cross += weight(i) * (target[i] - c.mean_target) * (source[i] - c.mean_source).transpose();
  return c;
}

using Svd3 = Eigen::JacobiSVD<Eigen::Matrix3d>;

Svd3 DecomposeCross(const Eigen::Matrix3d& H) { return Svd3(H, Eigen::ComputeFullU | Eigen::ComputeFullV); }

// For H = U D V^T the rotation closest to U V^T is U S V^T with S = diag(1, 1, -1) when U V^T would be a
// reflection (det U det V < 0), else S = I.
Eigen::Matrix3d ReflectionGuard(const Svd3& svd) {
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
  return S;
}

}  // namespace

Expected<Similarity> Umeyama(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  assert(source.size() == target.size());
  const std::size_t count = source.size();
  if (count < 3)
    return Status::Error("alignment needs at least 3 matched pairs, got " + std::to_string(count));
  const double n = static_cast<double>(count);

  // sigma_x^2 = 1/n sum |x_i - mean_x|^2, Sigma_xy = 1/n sum (y_i - mean_y)(x_i - mean_x)^T
  const Correlation c = Correlate(source, target, {});
  double variance_source = 0;
  for (const Eigen::Vector3d& x : source) variance_source += (x - c.mean_source).squaredNorm();
  variance_source /= n;
  const Svd3 svd = DecomposeCross(c.cross / n);
  const Eigen::Vector3d d = svd.singularValues();
  // Rank below 2 means the points lie on a line (or coincide): rotation about that line is unobservable.
  // evo tests d > machine epsilon in absolute terms; a relative test also catches lines that are noisy at the
  // rounding level.
  if (!(d[1] > 1e-12 * d[0]) || !(variance_source > 0))
    return Status::Error("degenerate alignment: the " + std::to_string(count) +
                         " matched positions are collinear or coincide, so the rotation is undetermined "
                         "(use --align none)");

  const Eigen::Matrix3d S = ReflectionGuard(svd);
  Similarity result;
  result.rotation = SO3(Eigen::Matrix3d(svd.matrixU() * S * svd.matrixV().transpose()));
  result.scale = with_scale ? (d.asDiagonal() * S).trace() / variance_source : 1.0;
  result.translation = c.mean_target - result.scale * (result.rotation.matrix() * c.mean_source);
  return result;
}

SE3 WeightedRigidAlignment(std::span<const Eigen::Vector3d> source, std::span<const Eigen::Vector3d> target,
                           std::span<const double> weights, bool yaw_only) {
  assert(weights.size() == source.size());
  const Correlation c = Correlate(source, target, weights);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (yaw_only) {
    double s = 0, cos_sum = 0;
    for (std::size_t i = 0; i < source.size(); ++i) {
      const Eigen::Vector3d a = source[i] - c.mean_source, f = target[i] - c.mean_target;
      s += weights[i] * (a.x() * f.y() - a.y() * f.x());
      cos_sum += weights[i] * (a.x() * f.x() + a.y() * f.y());
    }
    R = Eigen::AngleAxisd(std::atan2(s, cos_sum), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  } else {
    const Svd3 svd = DecomposeCross(c.cross);
    R = svd.matrixU() * ReflectionGuard(svd) * svd.matrixV().transpose();
  }
  return SE3(SO3(R), c.mean_target - R * c.mean_source);
}

}  // namespace uf
