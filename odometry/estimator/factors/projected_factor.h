// A pose factor whose tangent Jacobians are taken through a projector P (6x6, the same for every pose
// block): J_i' = J_i P. The residual is the wrapped factor's. Used to drop a LiDAR scan's information along
// its weak directions (schedule/lidar_degeneracy.h, WeakDirectionProjector): a solver then moves the poses
// along them only as the other factors say. Every block of the wrapped factor must be a pose (7 ambient, 6
// tangent) and the factor a TangentJacobianCost.
#pragma once

#include <ceres/cost_function.h>

#include <memory>

#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

class ProjectedFactor : public ceres::CostFunction, public TangentJacobianCost {
 public:
  // `factor` (not null) implements TangentJacobianCost and has only pose blocks (asserted).
  ProjectedFactor(std::unique_ptr<ceres::CostFunction> factor, const Matrix6d& projector);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  std::unique_ptr<ceres::CostFunction> factor_;
  const TangentJacobianCost* tangent_;
  Matrix6d projector_;
};

}  // namespace uf::estimator
