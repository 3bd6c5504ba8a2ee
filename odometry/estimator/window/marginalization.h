// Marginalization of the oldest states of the sliding window into a Gaussian prior (Schur complement with
// eigenvalue truncation), in the spirit of VINS-Mono's MarginalizationInfo, written for our pose manifold.
//
// Usage (one marginalization step):
//   Marginalizer m(config);
//   m.SetPoseBlock(pose_k) for every pose block involved;   // others are Euclidean
//   m.AddResidualBlock(cost, loss, {blocks...}) for the window's factors (those not touching a marginalized
//     block are ignored), including the previous prior: m.AddPrior(previous_factor);
//   m.MarginalizeBlock(oldest_pose); m.MarginalizeBlock(oldest_speed_bias);
//   Expected<std::shared_ptr<MarginalizationPrior>> prior = m.Compute();
// then replace the previous prior in the problem by MarginalizationFactor(prior) on prior->ParameterBlocks()
// and remove the marginalized blocks (and their factors) from the problem.
//
// Compute evaluates the collected residual blocks at the blocks' current values (the linearisation point),
// builds the Gauss-Newton system in the tangent spaces
//   H = sum J_i^T J_i,  b = -sum J_i^T r_i,   J_i = d r_i / d delta (ambient Jacobian x PlusJacobian),
// orders it [marginalized m | kept k] and takes the Schur complement
//   H* = H_kk - H_km H_mm^+ H_mk,   b* = b_k - H_km H_mm^+ b_m,
// with H_mm^+ the eigen-decomposition pseudo-inverse (eigenvalues <= threshold dropped). H* is then factored
// as J* = sqrt(L) V^T, r0 = -sqrt(L)^-1 V^T b* over the eigenpairs (L, V) of H* above the threshold, so
// J*^T J* = H* and J*^T r0 = -b* (b* lies in the range of H* up to the truncated directions).
//
// Robust losses: residuals are reweighted exactly as Ceres' solver does (ceres::internal::Corrector, Triggs
// et al.): with s = |r|^2 and rho'(s), rho''(s), r <- sqrt(rho')/(1 - alpha) r and
// J <- sqrt(rho') (I - alpha r r^T / s) J, alpha = 1 - sqrt(1 + 2 s rho''/rho') when rho'' > 0, else alpha =
// 0 (plain sqrt(rho') scaling, the case of Huber/Cauchy). The system is built by the window's dense solver
// (DenseLeastSquares::Linearize, every involved block free), so the prior carries exactly the information
// that the solver used at the linearisation point, from one implementation of the reweighting and of the
// tangent Jacobians.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <memory>
#include <unordered_set>
#include <vector>

#include "odometry/estimator/config/marginalization_config.h"
#include "odometry/estimator/window/marginalization_factor.h"
#include "odometry/types/status.h"

namespace uf::estimator {

// Step 4 below on its own: factors the information (H, b) of the prior's blocks (tangent order) into its J
// and r0, so that J^T J = H and J^T r0 = -b over the eigen-directions above the config's threshold. Error
// when none is, or when the result is not finite.
Status FactorInformation(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                         const MarginalizationConfig& config, MarginalizationPrior* prior);

class Marginalizer {
 public:
  explicit Marginalizer(MarginalizationConfig config = {});

  // Declares a block as a pose (7 ambient, PoseManifold); blocks not declared are Euclidean.
  void SetPoseBlock(double* block);
  // A residual block of the window. Cost and loss (loss may be null) are not owned and must stay alive until
  // Compute returns. Blocks not touching a marginalized block are ignored by Compute.
  void AddResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        std::vector<double*> parameter_blocks);
  // The previous prior, as a residual block on its kept blocks (pose kinds taken from its layout).
  void AddPrior(const MarginalizationFactor* prior);
  void MarginalizeBlock(double* block);

  // Evaluates, Schur-complements and factors (see top). Errors: invalid config, nothing to marginalize, no
  // residual touching the marginalized blocks, a pose block not of size 7, a failed or non-finite
  // evaluation, no kept block, or a prior without information (all eigenvalues truncated).
  Expected<std::shared_ptr<MarginalizationPrior>> Compute() const;

 private:
  struct ResidualBlock {
    const ceres::CostFunction* cost;
    const ceres::LossFunction* loss;
    std::vector<double*> parameter_blocks;
  };

  MarginalizationConfig config_;
  std::unordered_set<const double*> pose_blocks_;
  std::vector<double*> marginalized_;  // in insertion order (determinism)
  std::vector<ResidualBlock> residuals_;
};

}  // namespace uf::estimator
