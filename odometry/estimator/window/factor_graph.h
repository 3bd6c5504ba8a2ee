// The sliding window's factor graph, the same for every sensor (docs/METHOD.md "Sliding window and solve";
// paper Sec. III-B): parameter blocks (poses on PoseManifold; Euclidean blocks: speed and biases,
// calibration) and factor entries {kind, tag, cost, loss, blocks} that each modality's provider adds.
// Assembling a solve (dense Levenberg-Marquardt or Ceres), and folding leaving states into the
// marginalization prior, are generic over the entries: a new kind of factor is its cost function, its
// provider, and one line in FactorKind.
//
// Blocks live in the caller's storage at fixed addresses (the window's nodes); the graph only records how
// each block moves. Entries own their cost and loss. Solves visit the entries kind by kind in FactorKind
// order, within a kind in insertion order, then the prior: the order in which the dense solver sums them,
// so results do not depend on anything but the calls made.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "odometry/estimator/config/marginalization_config.h"
#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/estimator/window/marginalization_factor.h"
#include "odometry/types/status.h"

namespace uf::estimator {

class DenseLeastSquares;

// Solve order. Adding a kind: one line here and its name in factor_graph.cpp.
enum class FactorKind { kMotionPrior, kImu, kWheel, kGnss, kLidar, kVisual, kStatePrior };
constexpr int kFactorKinds = 7;
const char* FactorKindName(FactorKind kind);

struct Factor {
  FactorKind kind = FactorKind::kMotionPrior;
  long tag = 0;  // the provider's key (the node a motion factor ends at, a scan's id): see Remove
  std::unique_ptr<ceres::CostFunction> cost;
  std::unique_ptr<ceres::LossFunction> loss;  // null: plain least squares
  std::vector<double*> blocks;                // in the cost function's parameter order
  // Ties the states to something outside the window's own motion (the map, the Earth). Motion factors (IMU,
  // wheel, constant velocity) do not: a prior made only of them would leave the window's gauge free.
  bool anchors = false;
  // The cost as a TangentJacobianCost, or null when it is not one: cast once by Add, not at every solve.
  const TangentJacobianCost* tangent = nullptr;
  // Set by Add (and ReplaceCosts), never reused: names the entry for the condensed models' cache. An entry's
  // cost is changed through ReplaceCosts only.
  std::uint64_t serial = 0;
};

enum class WindowSolver { kDense, kCeres };

struct WindowSolveRequest {
  std::vector<double*> free;  // the blocks the solve moves, in tangent order; every other block is constant
  // Which entries take part (default: all). Only entries touching a free block are added to the problem.
  std::function<bool(const Factor&)> use;
  bool use_prior = true;
  WindowSolver solver = WindowSolver::kDense;
  int max_iterations = 8;
  double max_time_s = 0.04;
  // Entries solved on their Gauss-Newton model (window/condensed_factor.h; dense solver only): each run of
  // consecutive entries passing `condense` on the same blocks becomes one linear factor. A model is kept
  // from solve to solve while its entries and free blocks stay the same and its blocks stay within the
  // relinearization thresholds below of its linearization point; past them it is condensed again. After a
  // solve the models that moved past them are condensed again and the window solved again, at most
  // `condensed_rounds` solves in all (each with the iteration budget above, the time budget shared).
  // Default: none, every entry solved as it is.
  std::function<bool(const Factor&)> condense;
  int condensed_rounds = 2;
  double relinearize_translation_m = 0.005;  // a pose block's translation, m
  double relinearize_rotation_rad = 5e-4;    // a pose block's rotation angle, rad
  double relinearize_euclidean = 1e-3;       // any coordinate of a Euclidean block
  MarginalizationConfig condense_config;     // where the models' eigenvalues count as zero
};

struct WindowSolveResult {
  int iterations = 0;   // as Ceres' summary.iterations.size()
  bool usable = false;  // false: the solver failed (values may have moved; the caller restores them)
};

class FactorGraph {
 public:
  void AddPoseBlock(double* block);  // 7 ambient {t, q}, PoseManifold
  void AddEuclideanBlock(double* block, int size);
  // Forgets blocks and removes every entry touching one of them, and the prior when it does (their
  // information is dropped; Marginalize keeps it instead).
  void RemoveBlocks(const std::vector<double*>& blocks);
  bool IsPoseBlock(const double* block) const;

  void Add(Factor factor);
  void Add(FactorKind kind, long tag, std::unique_ptr<ceres::CostFunction> cost,
           std::unique_ptr<ceres::LossFunction> loss, std::vector<double*> blocks, bool anchors = false);
  // Removes the entries of `kind` with `tag`.
  void Remove(FactorKind kind, long tag);
  // Replaces the cost of each entry of `kind` with `tag` by wrap(its cost) (a ProjectedFactor around it,
  // say). The way to change an entry's cost: the entry is then one the solves have not seen (its
  // TangentJacobianCost cast again, a new serial, so no condensed model of the old cost serves it).
  void ReplaceCosts(
      FactorKind kind, long tag,
      const std::function<std::unique_ptr<ceres::CostFunction>(std::unique_ptr<ceres::CostFunction>)>& wrap);
  std::vector<Factor>& Entries(FactorKind kind) { return entries_[static_cast<int>(kind)]; }
  const std::vector<Factor>& Entries(FactorKind kind) const { return entries_[static_cast<int>(kind)]; }
  int Count(FactorKind kind, long tag) const;
  // Everything: blocks, entries and the prior (a re-initialization).
  void Clear();

  const MarginalizationFactor* prior() const { return prior_.get(); }
  void DropPrior() { prior_.reset(); }

  WindowSolveResult Solve(const WindowSolveRequest& request);

  // Folds the blocks of `leaving` into the prior: the entries touching any of them and the previous prior
  // (when it touches one) are linearized at the current values and Schur-complemented onto the blocks they
  // connect to (window/marginalization.h); those entries are removed, the new prior replaces the old one,
  // and the leaving blocks are forgotten. Without an anchoring entry or a previous prior among them nothing
  // would pin the kept states, so the entries are dropped and no prior is made. A failed computation drops
  // the prior (the caller then holds its oldest state constant) and returns the reason.
  Status Marginalize(const std::vector<double*>& leaving, const MarginalizationConfig& config);

 private:
  struct BlockInfo {
    int size = 0;
    bool pose = false;
  };
  template <typename Visit>
  void ForEachUsed(const WindowSolveRequest& request, const std::unordered_set<const double*>& free,
                   Visit&& visit);
  WindowSolveResult SolveDense(const WindowSolveRequest& request,
                               const std::unordered_set<const double*>& free);
  // A run of condensed entries (those from `first` to `last` by serial, `count` of them) and its model.
  struct CondensedModel {
    FactorKind kind = FactorKind::kLidar;
    std::uint64_t first = 0, last = 0;
    std::size_t count = 0;
    std::unique_ptr<MarginalizationFactor> factor;
    bool used = false;  // in the current solve
  };
  // Adds `entries` (the used ones passing request.condense, in solve order) to `problem` as their runs'
  // models (kept ones, or condensed anew at the current values), or as themselves where a run could not be
  // condensed. Returns how many models were condensed anew.
  int AddCondensed(const WindowSolveRequest& request, const std::unordered_set<const double*>& free,
                   const std::vector<const Factor*>& entries, DenseLeastSquares& problem);
  // Whether a kept model still serves: the same free blocks, each within the request's thresholds.
  bool ModelHolds(const MarginalizationPrior& model, const std::vector<double*>& blocks,
                  const std::unordered_set<const double*>& free, const WindowSolveRequest& request) const;

  std::unordered_map<const double*, BlockInfo> blocks_;
  std::array<std::vector<Factor>, kFactorKinds> entries_;
  std::unique_ptr<MarginalizationFactor> prior_;
  std::vector<CondensedModel> condensed_;  // the models of the last solve that condensed
  std::uint64_t next_serial_ = 1;
  PoseManifold manifold_;
};

}  // namespace uf::estimator
