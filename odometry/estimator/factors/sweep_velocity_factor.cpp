#include "odometry/estimator/factors/sweep_velocity_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

struct SweepVelocityResidual {
  double inverse_dt_reference, inverse_dt_sweep, inverse_sigma;

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, const T* begin, const T* end, T* residuals) const {
    for (int i = 0; i < 3; ++i)
      residuals[i] =
          ((end[i] - begin[i]) * inverse_dt_sweep - (pose_b[i] - pose_a[i]) * inverse_dt_reference) *
          inverse_sigma;
    return true;
  }
};

}  // namespace

std::unique_ptr<ceres::CostFunction> MakeSweepVelocityFactor(const SweepVelocityTiming& timing,
                                                             double acc_density) {
  assert(timing.dt_reference > 0 && timing.dt_sweep > 0 && timing.dt_mid > 0 && acc_density > 0);
  return std::make_unique<ceres::AutoDiffCostFunction<SweepVelocityResidual, 3, 7, 7, 7, 7>>(
      new SweepVelocityResidual{1.0 / timing.dt_reference, 1.0 / timing.dt_sweep,
                                1.0 / (acc_density * std::sqrt(timing.dt_mid))});
}

}  // namespace uf::estimator
