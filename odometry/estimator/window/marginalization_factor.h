// The marginalization prior of the sliding window as a Ceres cost function.
//
// A prior is the Gaussian that remains of the residuals of marginalized states after the Schur complement
// (see marginalization.h). It is linear in the tangent of the kept blocks at the linearisation point x0:
//   r(x) = J* (x boxminus x0) + r0,   with J*^T J* = H*, J*^T r0 = -b*,
// where boxminus is PoseManifold::Minus (= [t - t0; Log(q0^-1 q)]) for pose blocks and x - x0 for Euclidean
// ones. Its cost 1/2 |r|^2 equals, up to a constant, 1/2 dx^T H* dx - b*^T dx.
//
// Blocks are referred to by address (the window's fixed-address storage) plus the layout recorded here.
// The window must keep every kept block alive while the prior is in the problem; when a kept block is itself
// marginalized, this prior is one of the residual blocks handed to the next marginalization, and the new
// prior replaces it (so a prior never outlives the blocks it refers to).
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace uf::estimator {

// How a parameter block moves: Euclidean (x + delta) or on PoseManifold ({t, q}, tangent [dt; dtheta]).
enum class BlockKind { kEuclidean, kPose };

struct BlockLayout {
  double* address = nullptr;  // the window's storage of the block (must stay valid, see above)
  int ambient_size = 0;       // 7 for a pose
  int tangent_size = 0;       // 6 for a pose
  BlockKind kind = BlockKind::kEuclidean;
};

// The linear prior: kept blocks in order, their values at linearisation (x0, ambient) and the factored
// information. Rows of J are the non-truncated eigen-directions of H*; columns follow the kept blocks'
// tangents in order.
struct MarginalizationPrior {
  std::vector<BlockLayout> kept;
  std::vector<std::vector<double>> linearization_point;  // x0 per kept block, ambient
  Eigen::MatrixXd J;                                     // rank x TangentSize()
  Eigen::VectorXd r0;                                    // rank

  int TangentSize() const;
  int Rank() const { return static_cast<int>(r0.size()); }
  // The kept blocks' addresses, in the order of the factor's parameter blocks (for AddResidualBlock).
  std::vector<double*> ParameterBlocks() const;
};

class MarginalizationFactor : public ceres::CostFunction {
 public:
  explicit MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior);

  // r = J* (x boxminus x0) + r0. Jacobians: the tangent Jacobian of a pose block is J*_block diag(I,
  // Jr^-1(Log(q0^-1 q))) (exact derivative of Log(q0^-1 q Exp(dtheta)) at 0), lifted to the ambient block
  // with TangentToAmbientJacobian so that Ceres' product with PlusJacobian gives it back.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  const MarginalizationPrior& prior() const { return *prior_; }

 private:
  std::shared_ptr<const MarginalizationPrior> prior_;
};

}  // namespace uf::estimator
