#include "odometry/estimator/calib/rotation_alignment.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace uf::estimator {
namespace {

struct Means {
  Eigen::Vector3d lidar = Eigen::Vector3d::Zero(), imu = Eigen::Vector3d::Zero();
  double weight = 0.0;
};

Means WeightedMeans(std::span<const RatePair> pairs) {
  Means m;
  for (const RatePair& p : pairs) {
    if (!(p.weight > 0)) continue;
    m.lidar += p.weight * p.lidar;
    m.imu += p.weight * p.imu;
    m.weight += p.weight;
  }
  if (m.weight > 0) {
    m.lidar /= m.weight;
    m.imu /= m.weight;
  }
  return m;
}

double Residual(const RotationFit& fit, const RatePair& p) {
  return (fit.R_imu_lidar * p.lidar + fit.gyro_bias - p.imu).norm();
}

void ScoreFit(std::span<const RatePair> pairs, double huber, RotationFit& fit) {
  double sum = 0, weight = 0;
  int inliers = 0, used = 0;
  for (const RatePair& p : pairs) {
    if (!(p.weight > 0)) continue;
    const double r = Residual(fit, p);
    ++used;
    if (huber > 0 && r > huber) continue;
    ++inliers;
    sum += p.weight * r * r;
    weight += p.weight;
  }
  fit.rms_residual = weight > 0 ? std::sqrt(sum / weight) : 0.0;
  fit.inlier_ratio = used > 0 ? static_cast<double>(inliers) / used : 0.0;
}

// k = max(k_min, 3 median|r| / 1.538) over the pairs with weight.
double HuberThreshold(std::span<const RatePair> pairs, const RotationFit& fit, double min_huber) {
  std::vector<double> r;
  for (const RatePair& p : pairs)
    if (p.weight > 0) r.push_back(Residual(fit, p));
  if (r.empty()) return min_huber;
  std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
  return std::max(min_huber, 3.0 * r[r.size() / 2] / 1.538);
}

}  // namespace

RotationFit FitRotation(std::span<const RatePair> pairs) {
  const Means m = WeightedMeans(pairs);
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (const RatePair& p : pairs)
    if (p.weight > 0) H += p.weight * (p.lidar - m.lidar) * (p.imu - m.imu).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (V * U.transpose()).determinant() < 0 ? -1.0 : 1.0;
  RotationFit fit;
  fit.R_imu_lidar = SO3(V * D * U.transpose());
  fit.gyro_bias = m.imu - fit.R_imu_lidar * m.lidar;
  ScoreFit(pairs, 0.0, fit);
  return fit;
}

RotationFit FitRotationRobust(std::span<const RatePair> pairs, double min_huber_rad_s, int iterations) {
  RotationFit fit = FitRotation(pairs);
  std::vector<RatePair> weighted(pairs.begin(), pairs.end());
  double huber_rad_s = min_huber_rad_s;
  for (int it = 0; it < iterations; ++it) {
    huber_rad_s = HuberThreshold(pairs, fit, min_huber_rad_s);
    // Huber's IRLS weight: 1 within the threshold, threshold / r beyond.
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const double r = Residual(fit, pairs[k]);
      weighted[k].weight = pairs[k].weight * (r <= huber_rad_s ? 1.0 : huber_rad_s / r);
    }
    fit = FitRotation(weighted);
  }
  ScoreFit(pairs, huber_rad_s, fit);
  fit.huber_rad_s = huber_rad_s;
  return fit;
}

double RotationSigma(std::span<const RatePair> pairs, const RotationFit& fit, double overlap) {
  const Means m = WeightedMeans(pairs);
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  for (const RatePair& p : pairs) {
    if (!(p.weight > 0)) continue;
    const Eigen::Matrix3d J = Hat(fit.R_imu_lidar * (p.lidar - m.lidar));
    information += p.weight * J.transpose() * J;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(information);
  const double smallest = eig.eigenvalues()[0];
  if (!(smallest > 0)) return std::numeric_limits<double>::infinity();
  const double variance = fit.rms_residual * fit.rms_residual / 3.0;
  return std::sqrt(variance * std::max(1.0, overlap) / smallest);
}

RotationExcitation MeasureRotationExcitation(std::span<const RatePair> pairs) {
  const Means m = WeightedMeans(pairs);
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  double spread = 0;
  for (const RatePair& p : pairs) {
    if (!(p.weight > 0)) continue;
    const Eigen::Vector3d d = p.lidar - m.lidar;
    spread += p.weight * d.squaredNorm();
    const double n = d.norm();
    if (n > 0) M += p.weight * (d / n) * (d / n).transpose();
  }
  RotationExcitation e;
  if (!(m.weight > 0)) return e;
  e.rate_spread_rad_s = std::sqrt(spread / m.weight);
  const double trace = M.trace();
  if (!(trace > 0)) return e;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M / trace);
  e.eigenvalues = eig.eigenvalues();
  e.ratio = e.eigenvalues[2] > 0 ? std::max(0.0, e.eigenvalues[0]) / e.eigenvalues[2] : 0.0;
  return e;
}

}  // namespace uf::estimator
