// The parameter blocks of a visual factor under test (test_reprojection_factor.cpp,
// test_landmark_plane_factor.cpp): the poses first (7 ambient, 6 tangent, on PoseManifold), then the scalars;
// and the factor's tangent Jacobian in one block by central differences through PoseManifold::Plus.
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <initializer_list>
#include <vector>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator::test {

struct FactorBlocks {
  std::vector<std::vector<double>> values;
  int poses = 0;

  static FactorBlocks Of(std::initializer_list<SE3> poses, std::initializer_list<double> scalars) {
    FactorBlocks b;
    for (const SE3& T : poses) {
      const auto block = PoseBlock(T);
      b.values.emplace_back(block.begin(), block.end());
    }
    b.poses = static_cast<int>(poses.size());
    for (double s : scalars) b.values.push_back({s});
    return b;
  }
  std::vector<const double*> Pointers() const {
    std::vector<const double*> p;
    for (const auto& v : values) p.push_back(v.data());
    return p;
  }
  int TangentSize(int k) const { return k < poses ? 6 : 1; }
};

inline Eigen::VectorXd Residuals(const ceres::CostFunction& f, const FactorBlocks& b) {
  Eigen::VectorXd r(f.num_residuals());
  f.Evaluate(b.Pointers().data(), r.data(), nullptr);
  return r;
}

// d r / d (tangent of block k) by central differences of step h: residuals x TangentSize(k).
inline Eigen::MatrixXd NumericTangentJacobian(const ceres::CostFunction& f, const FactorBlocks& b, int k,
                                              double h = 1e-7) {
  const int size = b.TangentSize(k);
  Eigen::MatrixXd numeric(f.num_residuals(), size);
  for (int i = 0; i < size; ++i) {
    Eigen::VectorXd rs[2];
    for (int sign = 0; sign < 2; ++sign) {
      FactorBlocks moved = b;
      std::vector<double> delta(size, 0.0);
      delta[i] = sign == 0 ? h : -h;
      if (k < b.poses)
        PoseManifold().Plus(b.values[k].data(), delta.data(), moved.values[k].data());
      else
        moved.values[k][0] += delta[0];
      rs[sign] = Residuals(f, moved);
    }
    numeric.col(i) = (rs[0] - rs[1]) / (2 * h);
  }
  return numeric;
}

}  // namespace uf::estimator::test
