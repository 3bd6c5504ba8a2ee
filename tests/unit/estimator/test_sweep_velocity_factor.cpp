// Sweep-velocity prior of LO on scans kept apart: zero when the sweep moves with the velocity of the last
// scan interval whatever the body turns, the hand-computed value on a velocity change, and its Jacobians
// (through PoseManifold) match central differences in the tangent [dt; dtheta].
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "odometry/estimator/factors/sweep_velocity_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

using Pose = std::array<double, kPoseSize>;
using Poses = std::array<Pose, 4>;  // a, b, begin, end

Eigen::Vector3d Residual(const ceres::CostFunction& f, const Poses& p) {
  const double* blocks[4] = {p[0].data(), p[1].data(), p[2].data(), p[3].data()};
  Eigen::Vector3d r;
  EXPECT_TRUE(f.Evaluate(blocks, r.data(), nullptr));
  return r;
}

// The interval a -> b of 0.4 s, a gap of 0.4 s, then a sweep of 0.1 s: middles 0.45 s apart.
constexpr SweepVelocityTiming kTiming{.dt_reference = 0.4, .dt_sweep = 0.1, .dt_mid = 0.45};

Pose At(const Eigen::Vector3d& position, double yaw) {
  return PoseBlock(SE3(SO3::Exp(Eigen::Vector3d(0, 0, yaw)), position));
}

TEST(SweepVelocityFactor, ZeroAtTheSameWorldVelocityWhileTheBodyTurns) {
  const Eigen::Vector3d v(1.2, -0.4, 0.1), p0(3, -2, 1);  // m/s, m
  const Poses poses = {At(p0, 0.0), At(p0 + 0.4 * v, 0.6), At(p0 + 0.8 * v, 1.1), At(p0 + 0.9 * v, 1.5)};
  EXPECT_LT(Residual(*MakeSweepVelocityFactor(kTiming, 0.5), poses).norm(), 1e-12);
}

TEST(SweepVelocityFactor, ResidualOfVelocityChange) {
  // Walking at 1 m/s along x, the sweep stretched to 3 m/s along y: r = (v_sweep - v_ab) / sigma with
  // sigma = 0.5 sqrt(0.45).
  const Poses poses = {At({0, 0, 0}, 0), At({0.4, 0, 0}, 0), At({0.8, 0, 0}, 0.3), At({0.8, 0.3, 0}, 0.4)};
  const double sigma = 0.5 * std::sqrt(0.45);
  const Eigen::Vector3d r = Residual(*MakeSweepVelocityFactor(kTiming, 0.5), poses);
  EXPECT_NEAR(r.x(), -1.0 / sigma, 1e-12);
  EXPECT_NEAR(r.y(), 3.0 / sigma, 1e-12);
  EXPECT_NEAR(r.z(), 0.0, 1e-12);
}

TEST(SweepVelocityFactor, JacobiansMatchNumericInTangent) {
  const Poses poses = {At({1, 2, 3}, 0.2), At({1.5, 2.1, 3.05}, 0.7), At({2.1, 2.0, 3.0}, 1.3),
                       At({2.2, 2.1, 2.9}, 1.4)};
  const auto f = MakeSweepVelocityFactor(kTiming, 0.5);
  const PoseManifold manifold;
  double J_ambient[4][3 * 7];
  double* jacobians[4] = {J_ambient[0], J_ambient[1], J_ambient[2], J_ambient[3]};
  const double* blocks[4] = {poses[0].data(), poses[1].data(), poses[2].data(), poses[3].data()};
  Eigen::Vector3d r0;
  ASSERT_TRUE(f->Evaluate(blocks, r0.data(), jacobians));
  for (int k = 0; k < 4; ++k) {
    double plus[7 * 6];
    manifold.PlusJacobian(poses[k].data(), plus);
    const Eigen::Matrix<double, 3, 6> J_tangent =
        Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>>(J_ambient[k]) *
        Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(plus);
    for (int j = 0; j < 6; ++j) {
      const double h = 1e-6;
      Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
      Poses up = poses, down = poses;
      delta[j] = h;
      manifold.Plus(poses[k].data(), delta.data(), up[k].data());
      delta[j] = -h;
      manifold.Plus(poses[k].data(), delta.data(), down[k].data());
      const Eigen::Vector3d numeric = (Residual(*f, up) - Residual(*f, down)) / (2 * h);
      EXPECT_LT((J_tangent.col(j) - numeric).norm(), 1e-5 * (1 + numeric.norm()))
          << "block " << k << " col " << j;
    }
  }
}

}  // namespace
}  // namespace uf::estimator
