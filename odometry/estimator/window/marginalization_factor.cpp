#include "odometry/estimator/window/marginalization_factor.h"

#include <Eigen/Geometry>
#include <cassert>

#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/types/so3.h"

namespace uf::estimator {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

int MarginalizationPrior::TangentSize() const {
  int size = 0;
  for (const BlockLayout& block : kept) size += block.tangent_size;
  return size;
}

std::vector<double*> MarginalizationPrior::ParameterBlocks() const {
  std::vector<double*> blocks;
  blocks.reserve(kept.size());
  for (const BlockLayout& block : kept) blocks.push_back(block.address);
  return blocks;
}

MarginalizationFactor::MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior)
    : prior_(std::move(prior)) {
  assert(prior_ != nullptr && prior_->Rank() > 0);
  assert(prior_->J.cols() == prior_->TangentSize());
  set_num_residuals(prior_->Rank());
  for (const BlockLayout& block : prior_->kept)
    mutable_parameter_block_sizes()->push_back(block.ambient_size);
}

bool MarginalizationFactor::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  const MarginalizationPrior& prior = *prior_;
  // dx = x boxminus x0 per block, stacked in the tangent.
  Eigen::VectorXd dx(prior.TangentSize());
  int offset = 0;
  for (size_t i = 0; i < prior.kept.size(); ++i) {
    const BlockLayout& block = prior.kept[i];
    const double* x0 = prior.linearization_point[i].data();
    if (block.kind == BlockKind::kPose) {
      PoseManifold().Minus(parameters[i], x0, dx.data() + offset);
    } else {
      for (int k = 0; k < block.tangent_size; ++k) dx[offset + k] = parameters[i][k] - x0[k];
    }
    offset += block.tangent_size;
  }
  Eigen::Map<Eigen::VectorXd>(residuals, prior.Rank()) = prior.J * dx + prior.r0;
  if (jacobians == nullptr) return true;

  offset = 0;
  for (size_t i = 0; i < prior.kept.size(); ++i) {
    const BlockLayout& block = prior.kept[i];
    if (jacobians[i] != nullptr) {
      const Eigen::MatrixXd J_block = prior.J.middleCols(offset, block.tangent_size);
      if (block.kind == BlockKind::kPose) {
        // d/d(delta) of [t + dt - t0; Log(q0^-1 q Exp(dtheta))] at delta = 0 is diag(I, Jr^-1(phi)) with
        // phi = Log(q0^-1 q) (right Jacobian, Barfoot 7.1.5).
        const Eigen::Vector3d phi = dx.segment<3>(offset + 3);
        RowMajorMatrix J_tangent = J_block;
        J_tangent.rightCols<3>() = J_block.rightCols<3>() * RightJacobianInverseSO3(phi);
        TangentToAmbientJacobian(parameters[i], J_tangent.data(), prior.Rank(), jacobians[i]);
      } else {
        Eigen::Map<RowMajorMatrix>(jacobians[i], prior.Rank(), block.ambient_size) = J_block;
      }
    }
    offset += block.tangent_size;
  }
  return true;
}

}  // namespace uf::estimator
