// Residual blocks on a few shared blocks (a scan's point-to-plane factors on its begin and end poses)
// replaced, for a solve, by their Gauss-Newton model at the blocks' current values: one linear factor in
// place of thousands of residuals (docs/METHOD.md "Sliding window and solve", the condensed LiDAR factors).
// With F(x) = 1/2 sum_i rho_i(|r_i(x)|^2) robust-reweighted as the dense solver does (J_i, r_i: its
// Linearize),
//
//   F(x0 boxplus dx) ~ F0 + g^T dx + 1/2 dx^T H dx = 1/2 |J* dx + r0|^2 + 1/2 c^2,
//   H = sum J_i^T J_i,  g = sum J_i^T r_i,  J*^T J* = H,  J*^T r0 = g,  c^2 = 2 F0 - |r0|^2,
//
// so the factor's cost equals F at x0 and its gradient and Gauss-Newton Hessian match there. The constant c
// is a residual row with zero Jacobian; it keeps the solver's relative tests (function tolerance, step
// acceptance) on the same scale as with the original residuals. What the model leaves out: the residuals'
// curvature in the rotation (a point at range d moves by d dtheta^2 / 2 to second order: 0.5 um at 50 m for
// a 1e-4 rad step) and the robust weights' change with the residual, which a solve refreshes by condensing
// again at its result.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <memory>
#include <vector>

#include "odometry/estimator/config/marginalization_config.h"
#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/estimator/window/marginalization_factor.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct CondensedInput {
  const ceres::CostFunction* cost = nullptr;
  const TangentJacobianCost* tangent = nullptr;  // the cost as one, or null
  const ceres::LossFunction* loss = nullptr;     // null: plain least squares
  const std::vector<double*>* blocks = nullptr;  // in the cost's parameter order
};

// The model above over `free` (the blocks the solve moves, each touched by some input; pose blocks are
// PoseManifold); blocks of the inputs not in `free` are held at their values. Error when an input fails to
// evaluate or the model has no information (every eigenvalue of H at or below the config's threshold).
Expected<std::unique_ptr<MarginalizationFactor>> CondenseResidualBlocks(
    const std::vector<CondensedInput>& inputs, const std::vector<BlockLayout>& free,
    const MarginalizationConfig& config);

}  // namespace uf::estimator
