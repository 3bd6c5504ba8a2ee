#include "odometry/estimator/factors/bias_prior_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

struct BiasPriorResidual {
  template <typename T>
  bool operator()(const T* speed_bias, T* residual) const {
    for (int i = 0; i < 3; ++i) {
      residual[i] = (speed_bias[3 + i] - T(accel_bias[i])) / sigma_accel;
      residual[3 + i] = (speed_bias[6 + i] - T(gyro_bias[i])) / sigma_gyro;
    }
    return true;
  }
  Eigen::Vector3d accel_bias, gyro_bias;
  double sigma_accel, sigma_gyro;
};

}  // namespace

std::unique_ptr<ceres::CostFunction> MakeBiasPriorFactor(const Eigen::Vector3d& accel_bias,
                                                         const Eigen::Vector3d& gyro_bias, double sigma_accel,
                                                         double sigma_gyro) {
  assert(std::isfinite(sigma_accel) && sigma_accel > 0 && std::isfinite(sigma_gyro) && sigma_gyro > 0);
  return std::make_unique<ceres::AutoDiffCostFunction<BiasPriorResidual, 6, 9>>(
      new BiasPriorResidual{accel_bias, gyro_bias, sigma_accel, sigma_gyro});
}

}  // namespace uf::estimator
