// Optional second interface of a Ceres cost function whose Jacobians are naturally taken in the tangent
// spaces of its blocks (PoseManifold's [dt; dtheta] for poses): solvers that know it (window/
// dense_least_squares.h) skip the ambient round trip J_tangent -> J_ambient (7 wide) -> J_ambient *
// PlusJacobian, which costs more than the residual itself for a point-to-plane factor.
#pragma once

namespace uf::estimator {

class TangentJacobianCost {
 public:
  virtual ~TangentJacobianCost() = default;
  // As ceres::CostFunction::Evaluate, but jacobians[i] (when not null) is residuals x tangent size of
  // block i, row-major: d r / d delta_i at delta_i = 0.
  virtual bool EvaluateTangent(double const* const* parameters, double* residuals,
                               double** tangent_jacobians) const = 0;
};

// Ceres' Evaluate from EvaluateTangent for a factor of `rows` residuals (at most kMaxLiftedRows) whose first
// `poses` (at most kMaxLiftedPoses) of `blocks` (at most kMaxLiftedBlocks) blocks are poses (7 ambient, 6
// tangent; lifted with TangentToAmbientJacobian) and whose others are Euclidean (the tangent is the ambient
// block).
inline constexpr int kMaxLiftedRows = 2, kMaxLiftedPoses = 3, kMaxLiftedBlocks = 5;
bool EvaluateLiftingPoses(const TangentJacobianCost& cost, int rows, int poses, int blocks,
                          double const* const* parameters, double* residuals, double** jacobians);

}  // namespace uf::estimator
