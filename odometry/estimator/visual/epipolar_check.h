// The epipolar check of the visual front end: a fundamental matrix fitted by RANSAC to point pairs in
// undistorted pixels (a distortion-free pinhole), and the Sampson distance of each pair to it.
//
// For a pair (x1, x2) in homogeneous pixels and the fundamental matrix F, x2^T F x1 = 0 for a static scene
// point. The Sampson distance is the first-order geometric distance of the pair from that constraint:
//   d^2 = (x2^T F x1)^2 / ((F x1)_0^2 + (F x1)_1^2 + (F^T x2)_0^2 + (F^T x2)_1^2).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

namespace uf::estimator {

struct EpipolarFit {
  bool fitted = false;         // false: fewer than 8 pairs, or RANSAC found no model; every pair is kept
  std::vector<bool> inlier;    // per pair
  double mean_sampson_px = 0;  // over the inliers (0 without a fit)
};

// Pairs with a Sampson distance above threshold_px are outliers.
EpipolarFit FitEpipolar(std::span<const Eigen::Vector2d> from, std::span<const Eigen::Vector2d> to,
                        double threshold_px, double confidence);

// The Sampson distance (px) of a pair from a fundamental matrix.
double SampsonDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2);

}  // namespace uf::estimator
