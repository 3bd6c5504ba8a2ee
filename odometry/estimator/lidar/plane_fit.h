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
};

// The moments of several sets taken relative to different origins, summed relative to one common origin:
// Add(m, s) for moments m whose d = p - o_m, with s = o_m - o (so d_common = d + s). Per set,
//   S_d  += S_d,m + N_m s,   S_dd += S_dd,m + S_d,m s^T + s S_d,m^T + N_m s s^T,
// and the last three terms are (v s^T) + (v s^T)^T with v = S_d,m + N_m s / 2: one outer product per set,
// its transpose added once in Total().
class ShiftedMomentSum {
 public:
  void Add(const PointMoments& m, const Eigen::Vector3d& shift) {
    if (m.count == 0) return;
    count_ += m.count;
    sum_ += m.sum + m.count * shift;
    outer_ += m.sum_outer;
    cross_.noalias() += (m.sum + (0.5 * m.count) * shift) * shift.transpose();
  }
  PointMoments Total() const {
    PointMoments total;
    total.count = count_;
    total.sum = sum_;
    total.sum_outer = outer_ + cross_ + cross_.transpose();
    return total;
  }

 private:
  int count_ = 0;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer_ = Eigen::Matrix3d::Zero(), cross_ = Eigen::Matrix3d::Zero();
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
