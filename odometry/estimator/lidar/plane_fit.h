// Local plane fitting by PCA for the LiDAR map: the plane {n, q, sigma} seen by the point-to-plane factor,
// and the running point moments (count, sum, sum of outer products) it is fitted from.
//
// Moments are kept relative to an origin o near the points (a voxel centre) so that the covariance
//   C = S_dd / N - m m^T,  m = S_d / N,  d = p - o
// stays exact to double precision far from the world origin. Moments with different origins are combined by
// shifting: for d' = d + s (s = o_1 - o_2), S_d' = S_d + N s and S_d'd' = S_dd + S_d s^T + s S_d^T + N s s^T.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace uf::estimator {

// A plane n^T (x - point) = 0 with unit normal (sign arbitrary) and thickness sigma = the standard deviation
// of the fitted points' distances to it (m, floored by the caller's min sigma).
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double sigma = 0;
};

struct PointMoments {
  int count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();        // sum of d = p - origin
  Eigen::Matrix3d sum_outer = Eigen::Matrix3d::Zero();  // sum of d d^T

  void Add(const Eigen::Vector3d& d) {
    ++count;
    sum += d;
    sum_outer.noalias() += d * d.transpose();
  }
  // Adds moments taken relative to an origin that lies at `shift` from this one (d_this = d_other + shift).
  void AddShifted(const PointMoments& other, const Eigen::Vector3d& shift);
};

struct PlaneFitGate {
  double max_eigen_ratio = 0.12;  // accept when lambda_min / lambda_mid <= this (eigenvalues of C)
  int min_points = 5;
  double min_sigma_m = 0.05;  // floor of the plane thickness (keeps 1 / sigma bounded on perfect planes)
};

// PCA plane of the moments (origin `origin`): normal = eigenvector of the smallest eigenvalue of C, point =
// the centroid, sigma = max(sqrt(lambda_min), gate.min_sigma_m). nullopt with fewer than gate.min_points, a
// degenerate spread (lambda_mid ~ 0: a line or a single point), or lambda_min / lambda_mid above the gate
// (an edge, a corner, vegetation).
std::optional<Plane> FitPlane(const PointMoments& moments, const Eigen::Vector3d& origin,
                              const PlaneFitGate& gate);

}  // namespace uf::estimator
