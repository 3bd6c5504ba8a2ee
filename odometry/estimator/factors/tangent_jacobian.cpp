#include "odometry/estimator/factors/tangent_jacobian.h"

#include <array>
#include <cassert>

#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {

bool EvaluateLiftingPoses(const TangentJacobianCost& cost, int rows, int poses, int blocks,
                          double const* const* parameters, double* residuals, double** jacobians) {
  assert(rows <= kMaxLiftedRows && poses <= kMaxLiftedPoses && blocks <= kMaxLiftedBlocks && poses <= blocks);
  if (jacobians == nullptr) return cost.EvaluateTangent(parameters, residuals, nullptr);
  std::array<std::array<double, kMaxLiftedRows * 6>, kMaxLiftedPoses> tangent{};
  std::array<double*, kMaxLiftedBlocks> J{};
  for (int i = 0; i < blocks; ++i)
    J[i] = i >= poses ? jacobians[i] : jacobians[i] != nullptr ? tangent[i].data() : nullptr;
  if (!cost.EvaluateTangent(parameters, residuals, J.data())) return false;
  for (int i = 0; i < poses; ++i)
    if (jacobians[i] != nullptr)
      TangentToAmbientJacobian(parameters[i], tangent[i].data(), rows, jacobians[i]);
  return true;
}

}  // namespace uf::estimator
