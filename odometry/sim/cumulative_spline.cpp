#include "odometry/sim/cumulative_spline.h"

#include <algorithm>
#include <cassert>

namespace uf::spline {

CumulativeBasis CumulativeBasisAt(double u) {
  const double u2 = u * u;
  const double u3 = u2 * u;
  CumulativeBasis basis;
  basis.value << 1.0, (5.0 + 3.0 * u - 3.0 * u2 + u3) / 6.0, (1.0 + 3.0 * u + 3.0 * u2 - 2.0 * u3) / 6.0,
      u3 / 6.0;
  basis.first << 0.0, 0.5 * (1.0 - u) * (1.0 - u), 0.5 + u - u2, 0.5 * u2;
  basis.second << 0.0, u - 1.0, 1.0 - 2.0 * u, u;
  return basis;
}

Eigen::Vector4d PositionWeights(double u) {
  const Eigen::Vector4d lambda = CumulativeBasisAt(u).value;
  return Eigen::Vector4d(lambda(0) - lambda(1), lambda(1) - lambda(2), lambda(2) - lambda(3), lambda(3));
}

SegmentCoordinate LocateSegment(Stamp t, Stamp begin, Stamp spacing, int segments) {
  assert(spacing > 0 && segments > 0);
  assert(t >= begin && (t - begin) / spacing <= segments);
  const Stamp offset = t - begin;
  // Integer division keeps nanosecond stamps exact; the end of the spline belongs to the last segment.
  const Stamp index = std::min<Stamp>(offset / spacing, segments - 1);
  return {static_cast<int>(index),
          static_cast<double>(offset - index * spacing) / static_cast<double>(spacing)};
}

PositionSegmentState EvaluatePositionSegment(const std::array<Eigen::Vector3d, 4>& control, double u,
                                             double spacing_seconds) {
  const CumulativeBasis basis = CumulativeBasisAt(u);
  PositionSegmentState state{control[0], Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int j = 1; j < 4; ++j) {
    const Eigen::Vector3d step = control[j] - control[j - 1];
    state.position += basis.value(j) * step;
    state.velocity += basis.first(j) * step;
    state.acceleration += basis.second(j) * step;
  }
  state.velocity /= spacing_seconds;
  state.acceleration /= spacing_seconds * spacing_seconds;
  return state;
}

RotationSegmentState EvaluateRotationSegment(const std::array<SO3, 4>& control, double u,
                                             double spacing_seconds) {
  // The recursion of Sommer et al. (2020), built up factor by factor. With R^(j) = R^(j-1) A_j and
  // A_j = Exp(lambda_j d_j), whose derivative is A_j^T dA_j/dt = Hat(dlambda_j/dt d_j):
  //   omega^(j)  = A_j^T omega^(j-1) + dlambda_j/dt d_j
  //   domega^(j) = A_j^T domega^(j-1) + dlambda_j/dt (A_j^T omega^(j-1)) x d_j + d2lambda_j/dt2 d_j,
  // the middle term from d/dt Exp(-lambda_j d_j) = -dlambda_j/dt Hat(d_j) Exp(-lambda_j d_j).
  const CumulativeBasis basis = CumulativeBasisAt(u);
  const double rate = 1.0 / spacing_seconds;
  RotationSegmentState state{control[0], Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int j = 1; j < 4; ++j) {
    const Eigen::Vector3d d = (control[j - 1].inverse() * control[j]).Log();
    const SO3 A = SO3::Exp(basis.value(j) * d);
    const Eigen::Matrix3d At = A.matrix().transpose();
    const double dlambda = basis.first(j) * rate;
    const double d2lambda = basis.second(j) * rate * rate;
    const Eigen::Vector3d carried_omega = At * state.angular_velocity;
    state.rotation = state.rotation * A;
    state.angular_acceleration =
        At * state.angular_acceleration + dlambda * carried_omega.cross(d) + d2lambda * d;
    state.angular_velocity = carried_omega + dlambda * d;
  }
  return state;
}

std::array<Eigen::Matrix3d, 4> RotationSegmentJacobians(const std::array<SO3, 4>& control, double u) {
  // Perturbing R_i on the right changes d_i = Log(R_{i-1}^T R_i) by Jr^-1(d_i) delta_i and d_{i+1} by
  // -Jl^-1(d_{i+1}) delta_i. A change e of d_j turns A_j = Exp(lambda_j d_j) into
  //   A_j Exp(lambda_j Jr(lambda_j d_j) e),
  // which moves R(u) = R_0 A_1 A_2 A_3 on the right by P_j^T times that, P_j = A_{j+1} ... A_3 (P_3 = I).
  // R_0 itself moves R(u) by P_0^T delta_0, P_0 = A_1 A_2 A_3.
  const Eigen::Vector4d lambda = CumulativeBasisAt(u).value;
  std::array<Eigen::Vector3d, 4> d;
  std::array<Eigen::Matrix3d, 4> after;  // P_j
  after[3].setIdentity();
  for (int j = 1; j < 4; ++j) d[j] = (control[j - 1].inverse() * control[j]).Log();
  for (int j = 3; j >= 1; --j) after[j - 1] = SO3::Exp(lambda(j) * d[j]).matrix() * after[j];

  std::array<Eigen::Matrix3d, 4> jacobians;
  jacobians[0] = after[0].transpose();
  for (int j = 1; j < 4; ++j) {
    const Eigen::Matrix3d through_A = lambda(j) * after[j].transpose() * RightJacobianSO3(lambda(j) * d[j]);
    jacobians[j] = through_A * RightJacobianInverseSO3(d[j]);
    jacobians[j - 1] -= through_A * LeftJacobianInverseSO3(d[j]);
  }
  return jacobians;
}

}  // namespace uf::spline
