// Constant-velocity prior of LO mode: residual on exact constant motion is zero, on a velocity change it
// equals the hand-computed value, and its Jacobians (through PoseManifold) match central differences in the
// tangent [dt; dtheta].
#include <gtest/gtest.h>

#include <array>

#include "odometry/estimator/factors/constant_velocity_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

using Pose = std::array<double, kPoseSize>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

Vector6 Residual(const ceres::CostFunction& f, const Pose& a, const Pose& b, const Pose& c) {
  const double* blocks[3] = {a.data(), b.data(), c.data()};
  Vector6 r;
  EXPECT_TRUE(f.Evaluate(blocks, r.data(), nullptr));
  return r;
}

TEST(ConstantVelocityFactor, ZeroOnConstantTwistWithUnequalGaps) {
  Vector6 xi;
  xi << 3.0, 0.5, -0.2, 0.1, -0.05, 0.3;  // body twist per second
  const SE3 T0 = SE3::Exp((Vector6() << 1, 2, 3, 0.2, -0.1, 0.4).finished());
  const double dt1 = 0.1, dt2 = 0.35;
  const Pose a = PoseBlock(T0), b = PoseBlock(T0 * SE3::Exp(xi * dt1)),
             c = PoseBlock(T0 * SE3::Exp(xi * (dt1 + dt2)));
  // Pure translation + rotation at constant twist: Log(R_a^T R_b) / dt equals the angular rate exactly; the
  // translation part of a screw motion differs between frames a and b only by the rotation of v (second
  // order), so check a pure-translation case for exact zero and the screw case loosely.
  const auto f = MakeConstantVelocityFactor(dt1, dt2, {});
  EXPECT_LT(Residual(*f, a, b, c).norm(), 0.2);
  Vector6 v;
  v << 3.0, 0.5, -0.2, 0, 0, 0;
  const Pose b2 = PoseBlock(T0 * SE3::Exp(v * dt1)), c2 = PoseBlock(T0 * SE3::Exp(v * (dt1 + dt2)));
  EXPECT_LT(Residual(*f, a, b2, c2).norm(), 1e-12);
}

TEST(ConstantVelocityFactor, ResidualOfVelocityChange) {
  // From rest (a = b) to 1 m/s along body x over dt2: r_v = (0 - 1) / sigma_v.
  const double dt1 = 0.2, dt2 = 0.2;
  ConstantVelocityNoise noise;
  noise.acc_density = 2.0;
  const auto f = MakeConstantVelocityFactor(dt1, dt2, noise);
  const Pose a = PoseBlock(SE3()), b = PoseBlock(SE3()),
             c = PoseBlock(SE3(SO3(), Eigen::Vector3d(1.0 * dt2, 0, 0)));
  const double sigma_v = 2.0 * std::sqrt(0.2);
  const Vector6 r = Residual(*f, a, b, c);
  EXPECT_NEAR(r[0], -1.0 / sigma_v, 1e-12);
  EXPECT_NEAR(r.tail<5>().norm(), 0.0, 1e-12);
}

TEST(ConstantVelocityFactor, JacobiansMatchNumericInTangent) {
  const SE3 Ta = SE3::Exp((Vector6() << 1, 2, 3, 0.3, -0.2, 0.9).finished());
  const SE3 Tb = Ta * SE3::Exp((Vector6() << 0.7, 0.1, 0.05, 0.02, 0.03, 0.1).finished());
  const SE3 Tc = Tb * SE3::Exp((Vector6() << 1.9, -0.2, 0.1, -0.04, 0.01, 0.25).finished());
  std::array<Pose, 3> poses = {PoseBlock(Ta), PoseBlock(Tb), PoseBlock(Tc)};
  const auto f = MakeConstantVelocityFactor(0.1, 0.25, {});
  const PoseManifold manifold;
  double J_ambient[3][6 * 7];
  double* jacobians[3] = {J_ambient[0], J_ambient[1], J_ambient[2]};
  const double* blocks[3] = {poses[0].data(), poses[1].data(), poses[2].data()};
  Vector6 r0;
  ASSERT_TRUE(f->Evaluate(blocks, r0.data(), jacobians));
  for (int k = 0; k < 3; ++k) {
    double plus[7 * 6];
    manifold.PlusJacobian(poses[k].data(), plus);
    const Eigen::Matrix<double, 6, 6> J_tangent =
        Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>>(J_ambient[k]) *
        Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(plus);
    for (int j = 0; j < 6; ++j) {
      const double h = 1e-6;
      Vector6 delta = Vector6::Zero();
      std::array<Pose, 3> up = poses, down = poses;
      delta[j] = h;
      manifold.Plus(poses[k].data(), delta.data(), up[k].data());
      delta[j] = -h;
      manifold.Plus(poses[k].data(), delta.data(), down[k].data());
      const Vector6 numeric =
          (Residual(*f, up[0], up[1], up[2]) - Residual(*f, down[0], down[1], down[2])) / (2 * h);
      EXPECT_LT((J_tangent.col(j) - numeric).norm(), 1e-5 * (1 + numeric.norm()))
          << "block " << k << " col " << j;
    }
  }
}

}  // namespace
}  // namespace uf::estimator
