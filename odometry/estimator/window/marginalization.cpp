#include "odometry/estimator/window/marginalization.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/window/dense_least_squares.h"

namespace uf::estimator {
namespace {

// Eigenvalues at or below this are treated as zero (see MarginalizationConfig).
double TruncationThreshold(const MarginalizationConfig& config, const Eigen::VectorXd& eigenvalues) {
  const double largest = eigenvalues.size() > 0 ? std::max(0.0, eigenvalues.maxCoeff()) : 0.0;
  return std::max(config.eigenvalue_threshold, config.relative_eigenvalue_threshold * largest);
}

}  // namespace

// H = V L V^T into J = sqrt(L) V^T, r0 = -sqrt(L)^-1 V^T b over the eigenvalues kept.
Status FactorInformation(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                         const MarginalizationConfig& config, MarginalizationPrior* prior) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(H);
  const double threshold = TruncationThreshold(config, eigen.eigenvalues());
  std::vector<int> directions;
  for (int i = 0; i < H.rows(); ++i) {
    if (eigen.eigenvalues()[i] > threshold) directions.push_back(i);
  }
  if (directions.empty()) return Status::Error("marginalization: the prior has no information left");
  const int rank = static_cast<int>(directions.size());
  prior->J.resize(rank, H.rows());
  prior->r0.resize(rank);
  for (int row = 0; row < rank; ++row) {
    const double sqrt_lambda = std::sqrt(eigen.eigenvalues()[directions[row]]);
    const Eigen::VectorXd v = eigen.eigenvectors().col(directions[row]);
    prior->J.row(row) = sqrt_lambda * v.transpose();
    prior->r0[row] = -v.dot(b) / sqrt_lambda;
  }
  if (!prior->J.allFinite() || !prior->r0.allFinite())
    return Status::Error("marginalization: non-finite prior");
  return Status();
}

Marginalizer::Marginalizer(MarginalizationConfig config) : config_(config) {}

void Marginalizer::SetPoseBlock(double* block) { pose_blocks_.insert(block); }

void Marginalizer::AddResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                                    std::vector<double*> parameter_blocks) {
  assert(cost != nullptr);
  assert(parameter_blocks.size() == cost->parameter_block_sizes().size());
  residuals_.push_back({cost, loss, std::move(parameter_blocks)});
}

void Marginalizer::AddPrior(const MarginalizationFactor* prior) {
  assert(prior != nullptr);
  for (const BlockLayout& block : prior->prior().kept) {
    if (block.kind == BlockKind::kPose) pose_blocks_.insert(block.address);
  }
  AddResidualBlock(prior, nullptr, prior->prior().ParameterBlocks());
}

void Marginalizer::MarginalizeBlock(double* block) {
  if (std::find(marginalized_.begin(), marginalized_.end(), block) == marginalized_.end()) {
    marginalized_.push_back(block);
  }
}

Expected<std::shared_ptr<MarginalizationPrior>> Marginalizer::Compute() const {
  if (Status status = config_.Validate(); !status.ok()) return status;
  if (marginalized_.empty()) return Status::Error("marginalization: no block to marginalize");
  const std::unordered_set<const double*> marginalized(marginalized_.begin(), marginalized_.end());

  // 1. The residual blocks touching a marginalized block, and the layout of every block they touch:
  //    marginalized blocks first (in MarginalizeBlock order), then kept ones in order of first appearance.
  std::vector<const ResidualBlock*> involved;
  for (const ResidualBlock& residual : residuals_) {
    if (std::any_of(residual.parameter_blocks.begin(), residual.parameter_blocks.end(),
                    [&](double* b) { return marginalized.count(b) > 0; })) {
      involved.push_back(&residual);
    }
  }
  if (involved.empty())
    return Status::Error("marginalization: no residual block touches the marginalized blocks");

  std::unordered_map<const double*, int> ambient_size;
  for (const ResidualBlock* residual : involved) {
    for (size_t i = 0; i < residual->parameter_blocks.size(); ++i) {
      const int size = residual->cost->parameter_block_sizes()[i];
      const double* block = residual->parameter_blocks[i];
      if (pose_blocks_.count(block) > 0 && size != kPoseSize) {
        return Status::Error("marginalization: pose block of size " + std::to_string(size) + ", expected 7");
      }
      auto [it, inserted] = ambient_size.emplace(block, size);
      if (!inserted && it->second != size) {
        return Status::Error("marginalization: block used with sizes " + std::to_string(it->second) +
                             " and " + std::to_string(size));
      }
    }
  }
  std::vector<BlockLayout> layout;
  std::unordered_map<const double*, int> tangent_offset;
  int marginalized_size = 0, total_size = 0;
  const auto add_block = [&](double* block) {
    if (tangent_offset.count(block) > 0) return;
    const bool pose = pose_blocks_.count(block) > 0;
    BlockLayout entry{block, ambient_size.at(block), pose ? kPoseTangentSize : ambient_size.at(block),
                      pose ? BlockKind::kPose : BlockKind::kEuclidean};
    tangent_offset[block] = total_size;
    total_size += entry.tangent_size;
    layout.push_back(entry);
  };
  for (double* block : marginalized_) {
    if (ambient_size.count(block) == 0) {
      return Status::Error("marginalization: a marginalized block is touched by no residual block");
    }
    add_block(block);
  }
  marginalized_size = total_size;
  for (const ResidualBlock* residual : involved) {
    for (double* block : residual->parameter_blocks) add_block(block);
  }
  const int kept_size = total_size - marginalized_size;
  if (kept_size == 0)
    return Status::Error("marginalization: no kept block (nothing for the prior to act on)");

  // 2. Gauss-Newton system in the tangent, H = sum J^T J, b = -sum J^T r, robust-reweighted as the solver
  //    does: the dense solver's linearization, with every involved block free in layout order.
  DenseLeastSquares system;
  for (const BlockLayout& block : layout) {
    if (block.kind == BlockKind::kPose) {
      system.AddPoseBlock(block.address);
    } else {
      system.AddEuclideanBlock(block.address, block.ambient_size);
    }
  }
  for (const ResidualBlock* residual : involved)
    system.AddResidualBlock(residual->cost, residual->loss, residual->parameter_blocks);
  double cost = 0;
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
  if (!system.Linearize(&cost, &H, &b))
    return Status::Error(
        "marginalization: a residual block failed to evaluate at the linearisation point "
        "(or gave non-finite values)");
  b = -b;

  // 3. Schur complement onto the kept blocks, H_mm inverted by truncated eigen-decomposition.
  const int m = marginalized_size, k = kept_size;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> mm(H.topLeftCorner(m, m));
  const double mm_threshold = TruncationThreshold(config_, mm.eigenvalues());
  const Eigen::VectorXd inverse_eigenvalues =
      (mm.eigenvalues().array() > mm_threshold).select(mm.eigenvalues().cwiseInverse(), 0.0);
  const Eigen::MatrixXd H_mm_inverse =
      mm.eigenvectors() * inverse_eigenvalues.asDiagonal() * mm.eigenvectors().transpose();
  const Eigen::MatrixXd H_km = H.bottomLeftCorner(k, m);
  Eigen::MatrixXd H_star = H.bottomRightCorner(k, k) - H_km * H_mm_inverse * H_km.transpose();
  H_star = 0.5 * (H_star + H_star.transpose()).eval();
  const Eigen::VectorXd b_star = b.tail(k) - H_km * (H_mm_inverse * b.head(m));

  // 4. Factor H* into J* and r0.
  auto prior = std::make_shared<MarginalizationPrior>();
  if (Status status = FactorInformation(H_star, b_star, config_, prior.get()); !status.ok()) return status;
  for (size_t i = 0; i < layout.size(); ++i) {
    if (tangent_offset.at(layout[i].address) < m) continue;
    prior->kept.push_back(layout[i]);
    prior->linearization_point.emplace_back(layout[i].address, layout[i].address + layout[i].ambient_size);
  }
  return prior;
}

}  // namespace uf::estimator
