#include "odometry/estimator/window/condensed_factor.h"

#include <algorithm>
#include <cmath>

#include "odometry/estimator/window/dense_least_squares.h"
#include "odometry/estimator/window/marginalization.h"

namespace uf::estimator {

Expected<std::unique_ptr<MarginalizationFactor>> CondenseResidualBlocks(
    const std::vector<CondensedInput>& inputs, const std::vector<BlockLayout>& free,
    const MarginalizationConfig& config) {
  DenseLeastSquares system;  // its Linearize: the same reweighting and tangent Jacobians as the solve's
  for (const BlockLayout& block : free) {
    if (block.kind == BlockKind::kPose) {
      system.AddPoseBlock(block.address);
    } else {
      system.AddEuclideanBlock(block.address, block.ambient_size);
    }
  }
  for (const CondensedInput& input : inputs)
    system.AddResidualBlock(input.cost, input.tangent, input.loss, *input.blocks);
  double cost = 0;
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  if (!system.Linearize(&cost, &H, &g))
    return Status::Error("condensed factor: a residual block failed to evaluate (or gave non-finite values)");
  auto model = std::make_shared<MarginalizationPrior>();
  if (Status status = FactorInformation(H, -g, config, model.get()); !status.ok()) return status;
  // The constant row c (see the header).
  const int rank = model->Rank();
  model->J.conservativeResize(rank + 1, Eigen::NoChange);
  model->J.row(rank).setZero();
  model->r0.conservativeResize(rank + 1);
  model->r0[rank] = std::sqrt(std::max(0.0, 2.0 * cost - model->r0.head(rank).squaredNorm()));
  model->kept = free;
  for (const BlockLayout& block : free)
    model->linearization_point.emplace_back(block.address, block.address + block.ambient_size);
  return std::make_unique<MarginalizationFactor>(std::move(model));
}

}  // namespace uf::estimator
