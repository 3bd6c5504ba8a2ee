#include "odometry/estimator/factors/constant_velocity_factor.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

struct ConstantVelocityResidual {
  double inverse_dt_ab, inverse_dt_bc, inverse_sigma_v, inverse_sigma_w;

  // Log(q_from^-1 q_to) as an angle-axis vector, and R_from^T (t_to - t_from).
  template <typename T>
  static void RelativeMotion(const T* from, const T* to, T* translation, T* rotation) {
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(from + 3), q_to(to + 3);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_from(from), t_to(to);
    const Eigen::Quaternion<T> q_rel = q_from.conjugate() * q_to;
    const T q_wxyz[4] = {q_rel.w(), q_rel.x(), q_rel.y(), q_rel.z()};
    ceres::QuaternionToAngleAxis(q_wxyz, rotation);  // angle in [-pi, pi] whatever the sign of w
    Eigen::Map<Eigen::Matrix<T, 3, 1>> out(translation);
    out = q_from.conjugate() * (t_to - t_from);
  }

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, const T* pose_c, T* residuals) const {
    T v_ab[3], w_ab[3], v_bc[3], w_bc[3];
    RelativeMotion(pose_a, pose_b, v_ab, w_ab);
    RelativeMotion(pose_b, pose_c, v_bc, w_bc);
    for (int i = 0; i < 3; ++i) {
      residuals[i] = (v_ab[i] * inverse_dt_ab - v_bc[i] * inverse_dt_bc) * inverse_sigma_v;
      residuals[3 + i] = (w_ab[i] * inverse_dt_ab - w_bc[i] * inverse_dt_bc) * inverse_sigma_w;
    }
    return true;
  }
};

}  // namespace

std::unique_ptr<ceres::CostFunction> MakeConstantVelocityFactor(double dt_ab, double dt_bc,
                                                                const ConstantVelocityNoise& noise) {
  assert(dt_ab > 0 && dt_bc > 0);
  assert(noise.acc_density > 0 && noise.angular_acc_density > 0);
  const double sqrt_dt_mid = std::sqrt(0.5 * (dt_ab + dt_bc));
  return std::make_unique<ceres::AutoDiffCostFunction<ConstantVelocityResidual, 6, 7, 7, 7>>(
      new ConstantVelocityResidual{1.0 / dt_ab, 1.0 / dt_bc, 1.0 / (noise.acc_density * sqrt_dt_mid),
                                   1.0 / (noise.angular_acc_density * sqrt_dt_mid)});
}

}  // namespace uf::estimator
