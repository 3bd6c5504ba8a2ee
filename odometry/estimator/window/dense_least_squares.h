// A small dense nonlinear least-squares solver (Levenberg-Marquardt) for problems with few free parameter
// blocks and many residuals: the LiDAR registration rounds of the window (one scan's begin/end poses, 12
// dof, ~1500 point-to-plane residuals) and the LO window solve (~20 poses). It takes the same Ceres cost
// functions, losses and pose manifold as ceres::Problem, but never builds a Jacobian matrix: each residual
// block's Jacobian goes straight into the normal equations, so there is no per-solve setup cost.
//
// Problem: minimise  F(x) = 1/2 sum_i rho_i(|r_i(x)|^2)  over the free blocks; blocks that appear in
// residuals but were not added are constant. Pose blocks move on PoseManifold ({t, q} ambient, tangent
// [dt; dtheta], x <- {t + dt, q Exp(dtheta)}); Euclidean blocks by x <- x + dx.
//
// Linearisation (tangent delta of all free blocks stacked, size n):
//   J_i = (d r_i / d ambient) * PlusJacobian            (Ceres' convention for cost functions), or
//   J_i straight from TangentJacobianCost::EvaluateTangent when the cost function offers it
//   robust reweighting of (r_i, J_i) exactly as Ceres' Corrector (Triggs et al.), see marginalization.h
//   H = sum J_i^T J_i,   g = sum J_i^T r_i
// LM step (Marquardt scaling, as Ceres' LEVENBERG_MARQUARDT with Jacobi scaling):
//   (H + mu D) dx = -g,   D = diag(max(H_kk, 1e-6)),   mu = 1 / trust region radius (initially 1e-4)
// A step is accepted when the relative decrease rho = (F(x) - F(x + dx)) / (model decrease) > 1e-3; then
// mu <- mu * max(1/3, 1 - (2 rho - 1)^3) and v = 2, else mu <- mu * v, v <- 2 v (Nielsen's rule).
// Stops after max_iterations steps, the time budget, |dF| / F < function_tolerance,
// |dx| < parameter_tolerance (|x| + parameter_tolerance) or max |g| < gradient_tolerance.
//
// Threads: the residual blocks are split into contiguous chunks (their number depends only on how many
// blocks there are) evaluated in parallel with TBB, each summing its own F, H and g; the chunks' sums are
// then added in chunk order, so results do not depend on the number of threads or their timing. Cost
// functions must therefore be safe to evaluate concurrently (const, or per-thread scratch).
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "odometry/estimator/factors/tangent_jacobian.h"

namespace uf::estimator {

struct DenseSolverOptions {
  int max_iterations = 8;            // LM steps, accepted or rejected
  double max_time_s = 0.04;          // wall-time budget of one Solve, s
  double function_tolerance = 1e-6;  // as Ceres' defaults
  double parameter_tolerance = 1e-8;
  double gradient_tolerance = 1e-10;
  double initial_mu = 1e-4;  // 1 / Ceres' initial_trust_region_radius
};

struct DenseSolverSummary {
  int iterations = 0;       // as Ceres' summary.iterations.size(): 1 (the start) + the steps taken
  double initial_cost = 0;  // F at the start
  double final_cost = 0;    // F at the end
  bool usable = false;      // false: the start did not evaluate, or no step could be solved
  bool converged = false;   // stopped by a tolerance (not by the budget)
};

class DenseLeastSquares {
 public:
  // Free blocks, in the order of the tangent vector. A block must be added once.
  void AddPoseBlock(double* pose);  // 7 ambient (t, q x y z w), 6 tangent
  void AddEuclideanBlock(double* block, int size);
  // Cost (and loss, may be null) are not owned and must outlive Solve. Blocks not added above are constant.
  void AddResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        const std::vector<double*>& blocks);
  // The same with the cost's TangentJacobianCost given (`cost` itself, or null when it is not one), for
  // callers that cast each cost once rather than at every solve (FactorGraph).
  void AddResidualBlock(const ceres::CostFunction* cost, const TangentJacobianCost* tangent,
                        const ceres::LossFunction* loss, const std::vector<double*>& blocks);

  int TangentSize() const { return tangent_size_; }
  int NumResidualBlocks() const { return static_cast<int>(residuals_.size()); }

  // Optimises the free blocks in place.
  DenseSolverSummary Solve(const DenseSolverOptions& options);

  // F(x) at the current values and (optional) the robustified normal equations H, g; false when a cost
  // function fails or returns non-finite values.
  bool Linearize(double* cost, Eigen::MatrixXd* H, Eigen::VectorXd* g);

 private:
  struct Block {
    double* data;
    int ambient_size, tangent_size, offset;
    bool pose;
  };
  struct ResidualBlock {
    const ceres::CostFunction* cost;
    const TangentJacobianCost* tangent;  // the same object when it offers tangent Jacobians, else null
    const ceres::LossFunction* loss;
    int first_param;  // into params_ (block pointers), free_ (index into blocks_ or -1) and local_offset_
    int num_params;
    int local_size;  // tangent size of its free blocks side by side
    int group;       // consecutive residual blocks on the same free blocks share a group
  };
  // What one chunk of residual blocks sums (see EvaluateChunk), with its scratch buffers.
  struct Accumulator {
    bool ok = true;
    double cost = 0;
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    // Scratch.
    std::vector<double> residual, tangent_columns, J;
    std::vector<double*> jacobian_pointers;
    int group = -1, group_first = 0;  // the current local system: its group and one of its residual blocks
    Eigen::MatrixXd group_H;
    Eigen::VectorXd group_g;
    Eigen::Matrix<double, 12, 12> group_H12;  // fast path: one residual on two poses
    Eigen::Matrix<double, 12, 1> group_g12;
  };

  bool Evaluate(double* cost, Eigen::MatrixXd* H, Eigen::VectorXd* g);
  void EvaluateChunk(int first, int last, bool jacobians, Accumulator& sum) const;
  void FlushGroup(Accumulator& sum) const;
  void Plus(const Eigen::VectorXd& dx);  // x <- x boxplus dx
  std::vector<double> SaveValues() const;
  void RestoreValues(const std::vector<double>& values);

  std::vector<Block> blocks_;
  std::unordered_map<const double*, int> block_of_;
  int tangent_size_ = 0;
  std::vector<ResidualBlock> residuals_;
  std::vector<double*> params_;
  std::vector<int> free_;
  std::vector<int> local_offset_;  // of the parameter in its residual block's local system, -1 when constant
  std::vector<Accumulator> chunks_;
};

}  // namespace uf::estimator
