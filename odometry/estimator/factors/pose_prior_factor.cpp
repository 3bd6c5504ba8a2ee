#include "odometry/estimator/factors/pose_prior_factor.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

struct PosePriorResidual {
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (pose[i] - T(t0[i])) / sigma_translation;
    // Ceres' quaternions are (w, x, y, z); the pose block's are (x, y, z, w).
    const T q[4] = {pose[6], pose[3], pose[4], pose[5]};
    const T q0_inverse[4] = {T(q0.w()), T(-q0.x()), T(-q0.y()), T(-q0.z())};
    T delta[4];
    ceres::QuaternionProduct(q0_inverse, q, delta);
    const T sign = delta[0] < T(0) ? T(-1) : T(1);
    for (int i = 0; i < 3; ++i) residual[3 + i] = T(2) * sign * delta[1 + i] / sigma_rotation;
    return true;
  }
  Eigen::Vector3d t0;
  Eigen::Quaterniond q0;
  double sigma_translation, sigma_rotation;
};

}  // namespace

std::unique_ptr<ceres::CostFunction> MakePosePriorFactor(const SE3& T0, double sigma_translation_m,
                                                         double sigma_rotation_rad) {
  assert(std::isfinite(sigma_translation_m) && sigma_translation_m > 0);
  assert(std::isfinite(sigma_rotation_rad) && sigma_rotation_rad > 0);
  return std::make_unique<ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7>>(
      new PosePriorResidual{T0.translation(), Eigen::Quaterniond(T0.rotation()).normalized(),
                            sigma_translation_m, sigma_rotation_rad});
}

}  // namespace uf::estimator
