#include "odometry/estimator/factors/zero_motion_factor.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

struct ZeroMotionResidual {
  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, const T* speed_bias_i, const T* speed_bias_j,
                  T* residual) const {
    for (int k = 0; k < 3; ++k) residual[k] = (pose_j[k] - pose_i[k]) / sigmas.translation_m;
    // Ceres' quaternions are (w, x, y, z); the pose block's are (x, y, z, w).
    const T q_i_inverse[4] = {pose_i[6], -pose_i[3], -pose_i[4], -pose_i[5]};
    const T q_j[4] = {pose_j[6], pose_j[3], pose_j[4], pose_j[5]};
    T delta[4];
    ceres::QuaternionProduct(q_i_inverse, q_j, delta);
    const T sign = delta[0] < T(0) ? T(-1) : T(1);
    for (int k = 0; k < 3; ++k) residual[3 + k] = T(2) * sign * delta[1 + k] / sigmas.rotation_rad;
    for (int k = 0; k < 3; ++k) {
      residual[6 + k] = speed_bias_i[k] / sigmas.velocity_mps;
      residual[9 + k] = speed_bias_j[k] / sigmas.velocity_mps;
    }
    return true;
  }
  ZeroMotionSigmas sigmas;
};

}  // namespace

std::unique_ptr<ceres::CostFunction> MakeZeroMotionFactor(const ZeroMotionSigmas& sigmas) {
  assert(std::isfinite(sigmas.translation_m) && sigmas.translation_m > 0);
  assert(std::isfinite(sigmas.rotation_rad) && sigmas.rotation_rad > 0);
  assert(std::isfinite(sigmas.velocity_mps) && sigmas.velocity_mps > 0);
  return std::make_unique<ceres::AutoDiffCostFunction<ZeroMotionResidual, 12, 7, 7, 9, 9>>(
      new ZeroMotionResidual{sigmas});
}

}  // namespace uf::estimator
