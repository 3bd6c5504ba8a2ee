#include "odometry/estimator/factors/gauge_prior_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

struct GaugePriorResidual {
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    // pose = {t, q_x, q_y, q_z, q_w}; R_00 = 1 - 2 (q_y^2 + q_z^2), R_10 = 2 (q_x q_y + q_w q_z).
    const T& x = pose[3];
    const T& y = pose[4];
    const T& z = pose[5];
    const T& w = pose[6];
    for (int i = 0; i < 3; ++i) residual[i] = (pose[i] - T(position[i])) / sigma_position;
    const T yaw = ceres::atan2(T(2) * (x * y + w * z), T(1) - T(2) * (y * y + z * z));
    const T difference = yaw - T(yaw0);
    residual[3] = ceres::atan2(ceres::sin(difference), ceres::cos(difference)) / sigma_yaw;  // in (-pi, pi]
    return true;
  }
  Eigen::Vector3d position;
  double yaw0, sigma_position, sigma_yaw;
};

}  // namespace

double Yaw(const SO3& R) {
  const Eigen::Matrix3d m = R.matrix();
  return std::atan2(m(1, 0), m(0, 0));
}

std::unique_ptr<ceres::CostFunction> MakeGaugePriorFactor(const SE3& T_world_imu, double sigma_position_m,
                                                          double sigma_yaw_rad) {
  assert(std::isfinite(sigma_position_m) && sigma_position_m > 0);
  assert(std::isfinite(sigma_yaw_rad) && sigma_yaw_rad > 0);
  return std::make_unique<ceres::AutoDiffCostFunction<GaugePriorResidual, 4, 7>>(new GaugePriorResidual{
      T_world_imu.translation(), Yaw(T_world_imu.so3()), sigma_position_m, sigma_yaw_rad});
}

}  // namespace uf::estimator
