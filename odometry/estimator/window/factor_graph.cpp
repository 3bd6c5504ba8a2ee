#include "odometry/estimator/window/factor_graph.h"

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <unordered_set>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/window/condensed_factor.h"
#include "odometry/estimator/window/dense_least_squares.h"
#include "odometry/estimator/window/marginalization.h"

namespace uf::estimator {
namespace {

bool Touches(const std::vector<double*>& blocks, const std::unordered_set<const double*>& set) {
  return std::any_of(blocks.begin(), blocks.end(), [&](const double* b) { return set.count(b) > 0; });
}

// Touches for the entries in turn, asking the set again only when an entry's blocks differ from the last
// ones asked about: a scan's point factors come in a row on the same blocks. It keeps a copy of them, so
// the entries may move (remove_if).
class TouchTest {
 public:
  explicit TouchTest(const std::unordered_set<const double*>& set) : set_(set) {}
  bool operator()(const std::vector<double*>& blocks) {
    if (!asked_ || blocks != last_) {
      last_ = blocks;
      touches_ = Touches(blocks, set_);
      asked_ = true;
    }
    return touches_;
  }

 private:
  const std::unordered_set<const double*>& set_;
  std::vector<double*> last_;
  bool asked_ = false, touches_ = false;
};

}  // namespace

const char* FactorKindName(FactorKind kind) {
  switch (kind) {
    case FactorKind::kMotionPrior:
      return "motion_prior";
    case FactorKind::kImu:
      return "imu";
    case FactorKind::kWheel:
      return "wheel";
    case FactorKind::kGnss:
      return "gnss";
    case FactorKind::kLidar:
      return "lidar";
    case FactorKind::kVisual:
      return "visual";
    case FactorKind::kStatePrior:
      return "state_prior";
  }
  return "?";
}

void FactorGraph::AddPoseBlock(double* block) { blocks_[block] = {kPoseSize, true}; }

void FactorGraph::AddEuclideanBlock(double* block, int size) {
  assert(size > 0);
  blocks_[block] = {size, false};
}

bool FactorGraph::IsPoseBlock(const double* block) const {
  const auto it = blocks_.find(block);
  return it != blocks_.end() && it->second.pose;
}

void FactorGraph::RemoveBlocks(const std::vector<double*>& blocks) {
  const std::unordered_set<const double*> gone(blocks.begin(), blocks.end());
  TouchTest touches_gone(gone);
  for (std::vector<Factor>& kind : entries_)
    kind.erase(
        std::remove_if(kind.begin(), kind.end(), [&](const Factor& f) { return touches_gone(f.blocks); }),
        kind.end());
  if (prior_ && Touches(prior_->prior().ParameterBlocks(), gone)) prior_.reset();
  for (const double* block : blocks) blocks_.erase(block);
}

void FactorGraph::Add(Factor factor) {
  assert(factor.cost && factor.blocks.size() == factor.cost->parameter_block_sizes().size());
  for ([[maybe_unused]] const double* block : factor.blocks) assert(blocks_.count(block));
  factor.tangent = dynamic_cast<const TangentJacobianCost*>(factor.cost.get());
  factor.serial = next_serial_++;
  entries_[static_cast<int>(factor.kind)].push_back(std::move(factor));
}

void FactorGraph::Add(FactorKind kind, long tag, std::unique_ptr<ceres::CostFunction> cost,
                      std::unique_ptr<ceres::LossFunction> loss, std::vector<double*> blocks, bool anchors) {
  Add(Factor{kind, tag, std::move(cost), std::move(loss), std::move(blocks), anchors, nullptr, 0});
}

void FactorGraph::Remove(FactorKind kind, long tag) {
  std::vector<Factor>& list = Entries(kind);
  list.erase(std::remove_if(list.begin(), list.end(), [&](const Factor& f) { return f.tag == tag; }),
             list.end());
}

void FactorGraph::ReplaceCosts(
    FactorKind kind, long tag,
    const std::function<std::unique_ptr<ceres::CostFunction>(std::unique_ptr<ceres::CostFunction>)>& wrap) {
  for (Factor& f : Entries(kind)) {
    if (f.tag != tag) continue;
    f.cost = wrap(std::move(f.cost));
    assert(f.cost && f.blocks.size() == f.cost->parameter_block_sizes().size());
    f.tangent = dynamic_cast<const TangentJacobianCost*>(f.cost.get());
    f.serial = next_serial_++;
  }
}

int FactorGraph::Count(FactorKind kind, long tag) const {
  const std::vector<Factor>& list = Entries(kind);
  return static_cast<int>(
      std::count_if(list.begin(), list.end(), [&](const Factor& f) { return f.tag == tag; }));
}

void FactorGraph::Clear() {
  blocks_.clear();
  for (std::vector<Factor>& kind : entries_) kind.clear();
  prior_.reset();
  condensed_.clear();
}

// The entries a solve uses, in solve order: those passing request.use and touching a free block (`free`:
// request.free as a set), then the prior (when asked for and present). `visit` gets the entry last (null for
// the prior).
template <typename Visit>
void FactorGraph::ForEachUsed(const WindowSolveRequest& request,
                              const std::unordered_set<const double*>& free, Visit&& visit) {
  TouchTest touches_free(free);
  for (const std::vector<Factor>& kind : entries_)
    for (const Factor& f : kind)
      if ((!request.use || request.use(f)) && touches_free(f.blocks))
        visit(f.cost.get(), f.tangent, f.loss.get(), f.blocks, &f);
  if (request.use_prior && prior_)
    visit(prior_.get(), dynamic_cast<const TangentJacobianCost*>(prior_.get()), nullptr,
          prior_->prior().ParameterBlocks(), static_cast<const Factor*>(nullptr));
}

bool FactorGraph::ModelHolds(const MarginalizationPrior& model, const std::vector<double*>& blocks,
                             const std::unordered_set<const double*>& free,
                             const WindowSolveRequest& request) const {
  std::size_t k = 0;  // the model's blocks are the run's free blocks, in order
  for (double* block : blocks) {
    if (!free.count(block)) continue;
    if (k >= model.kept.size() || model.kept[k].address != block) return false;
    const double* x0 = model.linearization_point[k].data();
    if (model.kept[k].kind == BlockKind::kPose) {
      const SE3 T0 = PoseFromBlock(x0), T = PoseFromBlock(block);
      if ((T.translation() - T0.translation()).norm() > request.relinearize_translation_m ||
          (T0.so3().inverse() * T.so3()).Log().norm() > request.relinearize_rotation_rad)
        return false;
    } else {
      for (int i = 0; i < model.kept[k].ambient_size; ++i)
        if (std::abs(block[i] - x0[i]) > request.relinearize_euclidean) return false;
    }
    ++k;
  }
  return k == model.kept.size();
}

int FactorGraph::AddCondensed(const WindowSolveRequest& request,
                              const std::unordered_set<const double*>& free,
                              const std::vector<const Factor*>& entries, DenseLeastSquares& problem) {
  int condensed = 0;
  std::vector<const Factor*> run;  // consecutive entries on the same blocks
  const auto flush = [&] {
    if (run.empty()) return;
    const Factor& first = *run.front();
    auto kept = std::find_if(condensed_.begin(), condensed_.end(), [&](const CondensedModel& m) {
      return m.kind == first.kind && m.first == first.serial && m.last == run.back()->serial &&
             m.count == run.size();
    });
    if (kept == condensed_.end() || !ModelHolds(kept->factor->prior(), first.blocks, free, request)) {
      std::vector<BlockLayout> layout;
      for (double* block : first.blocks) {
        if (!free.count(block)) continue;
        const BlockInfo& info = blocks_.at(block);
        layout.push_back({block, info.size, info.pose ? kPoseTangentSize : info.size,
                          info.pose ? BlockKind::kPose : BlockKind::kEuclidean});
      }
      std::vector<CondensedInput> inputs;
      inputs.reserve(run.size());
      for (const Factor* f : run) inputs.push_back({f->cost.get(), f->tangent, f->loss.get(), &f->blocks});
      Expected<std::unique_ptr<MarginalizationFactor>> model =
          CondenseResidualBlocks(inputs, layout, request.condense_config);
      if (!model) {  // solved as they are
        for (const Factor* f : run)
          problem.AddResidualBlock(f->cost.get(), f->tangent, f->loss.get(), f->blocks);
        run.clear();
        return;
      }
      if (kept == condensed_.end()) kept = condensed_.insert(condensed_.end(), CondensedModel{});
      *kept = {first.kind, first.serial, run.back()->serial, run.size(), std::move(*model), false};
      ++condensed;
    }
    kept->used = true;
    const MarginalizationFactor* factor = kept->factor.get();
    problem.AddResidualBlock(factor, dynamic_cast<const TangentJacobianCost*>(factor), nullptr,
                             factor->prior().ParameterBlocks());
    run.clear();
  };
  for (const Factor* f : entries) {
    if (!run.empty() && run.front()->blocks != f->blocks) flush();
    run.push_back(f);
  }
  flush();
  return condensed;
}

// Dense: the window's few hundred tangent dimensions fit one dense normal-equation system, built straight
// from the residual blocks (dense_least_squares.h).
WindowSolveResult FactorGraph::SolveDense(const WindowSolveRequest& request,
                                          const std::unordered_set<const double*>& free) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  WindowSolveResult result;
  const int rounds = request.condense ? std::max(1, request.condensed_rounds) : 1;
  for (CondensedModel& model : condensed_) model.used = false;
  for (int round = 0; round < rounds; ++round) {
    DenseLeastSquares problem;
    for (double* block : request.free) {
      const BlockInfo& info = blocks_.at(block);
      if (info.pose) {
        problem.AddPoseBlock(block);
      } else {
        problem.AddEuclideanBlock(block, info.size);
      }
    }
    std::vector<const Factor*> to_condense;
    ForEachUsed(
        request, free,
        [&](const ceres::CostFunction* cost, const TangentJacobianCost* tangent,
            const ceres::LossFunction* loss, const std::vector<double*>& blocks, const Factor* entry) {
          if (entry && request.condense && request.condense(*entry)) {
            to_condense.push_back(entry);
          } else {
            problem.AddResidualBlock(cost, tangent, loss, blocks);
          }
        });
    // After the first solve, another only where a model was condensed anew (its blocks had moved past
    // the thresholds): else the last solve was on models that all still hold.
    const int condensed = request.condense ? AddCondensed(request, free, to_condense, problem) : 0;
    if (round > 0 && condensed == 0) break;
    DenseSolverOptions options;
    options.max_iterations = request.max_iterations;
    options.max_time_s = request.max_time_s - std::chrono::duration<double>(Clock::now() - start).count();
    if (round > 0 && options.max_time_s <= 0) break;
    const DenseSolverSummary summary = problem.Solve(options);
    result.iterations += summary.iterations;
    result.usable = summary.usable;
    if (!summary.usable) break;
  }
  if (request.condense) std::erase_if(condensed_, [](const CondensedModel& m) { return !m.used; });
  return result;
}

// Ceres: sparse Cholesky, for windows far larger than the dense solver's.
WindowSolveResult FactorGraph::Solve(const WindowSolveRequest& request) {
  WindowSolveResult result;
  const std::unordered_set<const double*> free(request.free.begin(), request.free.end());
  if (request.solver == WindowSolver::kDense) return SolveDense(request, free);
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.enable_fast_removal = false;
  ceres::Problem problem(problem_options);
  ForEachUsed(request, free,
              [&](const ceres::CostFunction* cost, const TangentJacobianCost*,
                  const ceres::LossFunction* loss, const std::vector<double*>& blocks, const Factor*) {
                for (double* block : blocks) {
                  if (problem.HasParameterBlock(block)) continue;
                  const BlockInfo& info = blocks_.at(block);
                  problem.AddParameterBlock(block, info.size, info.pose ? &manifold_ : nullptr);
                  if (!free.count(block)) problem.SetParameterBlockConstant(block);
                }
                problem.AddResidualBlock(const_cast<ceres::CostFunction*>(cost),
                                         const_cast<ceres::LossFunction*>(loss), blocks);
              });
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;  // J^T J block-banded
  options.max_num_iterations = request.max_iterations;
  options.max_solver_time_in_seconds = request.max_time_s;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.usable = summary.termination_type != ceres::FAILURE;
  return result;
}

Status FactorGraph::Marginalize(const std::vector<double*>& leaving, const MarginalizationConfig& config) {
  const std::unordered_set<const double*> gone(leaving.begin(), leaving.end());
  Marginalizer marginalizer(config);
  std::unordered_set<const double*> touched;  // leaving blocks some folded entry acts on
  bool anchored = false, any = false;
  for (const auto& [block, info] : blocks_)
    if (info.pose) marginalizer.SetPoseBlock(const_cast<double*>(block));
  TouchTest touches_gone(gone);
  for (const std::vector<Factor>& kind : entries_)
    for (const Factor& f : kind) {
      if (!touches_gone(f.blocks)) continue;
      marginalizer.AddResidualBlock(f.cost.get(), f.loss.get(), f.blocks);
      for (const double* b : f.blocks)
        if (gone.count(b)) touched.insert(b);
      anchored |= f.anchors;
      any = true;
    }
  const bool prior_leaves = prior_ && Touches(prior_->prior().ParameterBlocks(), gone);
  if (prior_leaves) {
    marginalizer.AddPrior(prior_.get());
    for (const double* b : prior_->prior().ParameterBlocks())
      if (gone.count(b)) touched.insert(b);
  }
  // A prior that does not touch the leaving blocks stays as it is (the entries are then dropped): the
  // window's own driver never gets there, since its prior always sits on the oldest kept states.
  Status status;
  if (prior_leaves || (!prior_ && any && anchored)) {
    for (double* block : leaving)
      if (touched.count(block)) marginalizer.MarginalizeBlock(block);
    Expected<std::shared_ptr<MarginalizationPrior>> computed = marginalizer.Compute();
    if (computed) {
      prior_ = std::make_unique<MarginalizationFactor>(*computed);
    } else {
      prior_.reset();
      status = computed.status();
    }
  }
  RemoveBlocks(leaving);
  return status;
}

}  // namespace uf::estimator
