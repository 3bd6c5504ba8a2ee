#include "odometry/estimator/factors/projected_factor.h"

#include <algorithm>
#include <cassert>
#include <vector>

#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {

ProjectedFactor::ProjectedFactor(std::unique_ptr<ceres::CostFunction> factor, const Matrix6d& projector)
    : factor_(std::move(factor)),
      tangent_(dynamic_cast<const TangentJacobianCost*>(factor_.get())),
      projector_(projector) {
  assert(tangent_ != nullptr);
  assert(std::all_of(factor_->parameter_block_sizes().begin(), factor_->parameter_block_sizes().end(),
                     [](int size) { return size == 7; }));
  set_num_residuals(factor_->num_residuals());
  *mutable_parameter_block_sizes() = factor_->parameter_block_sizes();
}

bool ProjectedFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                      double** jacobians) const {
  if (!tangent_->EvaluateTangent(parameters, residuals, jacobians)) return false;
  if (jacobians == nullptr) return true;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;
  for (std::size_t i = 0; i < factor_->parameter_block_sizes().size(); ++i) {
    if (jacobians[i] == nullptr) continue;
    Eigen::Map<RowMajor> J(jacobians[i], num_residuals(), 6);
    J = (J * projector_).eval();
  }
  return true;
}

bool ProjectedFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  if (jacobians == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  const std::size_t blocks = factor_->parameter_block_sizes().size();
  std::vector<std::vector<double>> tangent(blocks);
  std::vector<double*> tangent_pointers(blocks, nullptr);
  for (std::size_t i = 0; i < blocks; ++i) {
    if (jacobians[i] == nullptr) continue;
    tangent[i].resize(static_cast<std::size_t>(num_residuals()) * 6);
    tangent_pointers[i] = tangent[i].data();
  }
  if (!EvaluateTangent(parameters, residuals, tangent_pointers.data())) return false;
  for (std::size_t i = 0; i < blocks; ++i)
    if (jacobians[i] != nullptr)
      TangentToAmbientJacobian(parameters[i], tangent[i].data(), num_residuals(), jacobians[i]);
  return true;
}

}  // namespace uf::estimator
