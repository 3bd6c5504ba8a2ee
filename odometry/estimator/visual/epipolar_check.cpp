#include "odometry/estimator/visual/epipolar_check.h"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace uf::estimator {
namespace {

constexpr int kMinPairs = 8;  // the eight-point algorithm's minimum
constexpr int kMaxIterations = 1000;

std::vector<cv::Point2f> ToCv(std::span<const Eigen::Vector2d> points) {
  std::vector<cv::Point2f> out;
  out.reserve(points.size());
  for (const Eigen::Vector2d& p : points)
    out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  return out;
}

}  // namespace

double SampsonDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2) {
  const Eigen::Vector3d a = x1.homogeneous(), b = x2.homogeneous();
  const Eigen::Vector3d Fa = F * a, Ftb = F.transpose() * b;
  const double denominator = Fa.head<2>().squaredNorm() + Ftb.head<2>().squaredNorm();
  if (denominator <= 0) return 0;
  return std::abs(b.dot(Fa)) / std::sqrt(denominator);
}

EpipolarFit FitEpipolar(std::span<const Eigen::Vector2d> from, std::span<const Eigen::Vector2d> to,
                        double threshold_px, double confidence) {
  EpipolarFit fit;
  fit.inlier.assign(from.size(), true);
  if (from.size() < kMinPairs || from.size() != to.size()) return fit;
  std::vector<unsigned char> mask;
  const cv::Mat F = cv::findFundamentalMat(ToCv(from), ToCv(to), cv::FM_RANSAC, threshold_px, confidence,
                                           kMaxIterations, mask);
  // OpenCV may return up to three stacked solutions of the seven-point algorithm; RANSAC returns one.
  if (F.rows != 3 || F.cols != 3 || mask.size() != from.size()) return fit;
  Eigen::Matrix3d F_eigen;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) F_eigen(r, c) = F.at<double>(r, c);
  fit.fitted = true;
  double sum = 0;
  int inliers = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    fit.inlier[i] = mask[i] != 0;
    if (!fit.inlier[i]) continue;
    sum += SampsonDistance(F_eigen, from[i], to[i]);
    ++inliers;
  }
  fit.mean_sampson_px = inliers > 0 ? sum / inliers : 0;
  return fit;
}

}  // namespace uf::estimator
