#include "odometry/estimator/window/dense_least_squares.h"

#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>

#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr double kMinDiagonal = 1e-6;          // floor of the LM scaling D (Ceres' min_lm_diagonal)
// EvaluateChunk asks for the cost and loss objects of the residual block this many ahead (see there).
constexpr int kPrefetchAhead = 4;
constexpr int kPrefetchCostLines = 3;          // 64-byte lines: a point-to-plane factor spans 136 bytes
constexpr double kMinRelativeDecrease = 1e-3;  // a step must achieve this share of the model's decrease

// Whether two residual blocks act on the same free blocks in the same order: their parameters' free-block
// indices (-1: constant) with the constant ones skipped.
bool SameFreeBlocks(const int* a, int a_count, const int* b, int b_count) {
  int i = 0, j = 0;
  while (true) {
    while (i < a_count && a[i] < 0) ++i;
    while (j < b_count && b[j] < 0) ++j;
    if (i == a_count || j == b_count) return i == a_count && j == b_count;
    if (a[i++] != b[j++]) return false;
  }
}

}  // namespace

void DenseLeastSquares::AddPoseBlock(double* pose) {
  assert(!block_of_.count(pose));
  block_of_[pose] = static_cast<int>(blocks_.size());
  blocks_.push_back({pose, 7, 6, tangent_size_, true});
  tangent_size_ += 6;
}

void DenseLeastSquares::AddEuclideanBlock(double* block, int size) {
  assert(!block_of_.count(block) && size > 0);
  block_of_[block] = static_cast<int>(blocks_.size());
  blocks_.push_back({block, size, size, tangent_size_, false});
  tangent_size_ += size;
}

void DenseLeastSquares::AddResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                                         const std::vector<double*>& blocks) {
  AddResidualBlock(cost, dynamic_cast<const TangentJacobianCost*>(cost), loss, blocks);
}

void DenseLeastSquares::AddResidualBlock(const ceres::CostFunction* cost, const TangentJacobianCost* tangent,
                                         const ceres::LossFunction* loss,
                                         const std::vector<double*>& blocks) {
  assert(cost != nullptr && blocks.size() == cost->parameter_block_sizes().size());
  assert(tangent == dynamic_cast<const TangentJacobianCost*>(cost));
  ResidualBlock block{cost, tangent, loss, static_cast<int>(params_.size()), static_cast<int>(blocks.size()),
                      0,    0};
  // A scan's point factors come in a row on the same blocks: their lookups are the previous block's.
  const ResidualBlock* previous = residuals_.empty() ? nullptr : &residuals_.back();
  const bool as_previous = previous && previous->num_params == block.num_params &&
                           std::equal(blocks.begin(), blocks.end(), params_.begin() + previous->first_param);
  for (std::size_t p = 0; p < blocks.size(); ++p) {
    params_.push_back(blocks[p]);
    int index = -1;
    if (as_previous) {
      index = free_[previous->first_param + p];
    } else if (const auto it = block_of_.find(blocks[p]); it != block_of_.end()) {
      index = it->second;
    }
    free_.push_back(index);
    local_offset_.push_back(index < 0 ? -1 : block.local_size);
    if (index >= 0) block.local_size += blocks_[index].tangent_size;
  }
  // Same group as the previous block when both act on the same free blocks in the same order.
  if (!residuals_.empty()) {
    const ResidualBlock& previous = residuals_.back();
    const bool same = SameFreeBlocks(&free_[previous.first_param], previous.num_params,
                                     &free_[block.first_param], block.num_params);
    block.group = same ? previous.group : previous.group + 1;
  }
  residuals_.push_back(block);
}

bool DenseLeastSquares::Linearize(double* cost, Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  return Evaluate(cost, H, g);
}

// F and, when H is given, the robustified normal equations (see the header), summed over chunks of the
// residual blocks in parallel, then added in chunk order.
bool DenseLeastSquares::Evaluate(double* cost, Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  constexpr int kBlocksPerChunk = 512, kMaxChunks = 4;
  const int count = static_cast<int>(residuals_.size());
  const int chunks = std::clamp(count / kBlocksPerChunk, 1, kMaxChunks);
  if (static_cast<int>(chunks_.size()) < chunks) chunks_.resize(chunks);
  const bool jacobians = H != nullptr;
  tbb::parallel_for(0, chunks, [&](int c) {
    EvaluateChunk(static_cast<int>(static_cast<long>(count) * c / chunks),
                  static_cast<int>(static_cast<long>(count) * (c + 1) / chunks), jacobians, chunks_[c]);
  });
  double total = 0;
  for (int c = 0; c < chunks; ++c) {
    if (!chunks_[c].ok) return false;
    total += chunks_[c].cost;
    if (!jacobians) continue;
    if (c == 0) {
      *H = chunks_[c].H;
      *g = chunks_[c].g;
    } else {
      *H += chunks_[c].H;
      *g += chunks_[c].g;
    }
  }
  if (!std::isfinite(total)) return false;
  *cost = total;
  return true;
}

// F (and H, g) of the residual blocks [first, last). Each residual block's tangent Jacobian J (m x L, its
// free blocks side by side) is formed in scratch buffers; J^T J and J^T r are summed in a local L x L
// system while consecutive residual blocks act on the same free blocks, and scattered into H and g when
// that changes (FlushGroup).
void DenseLeastSquares::EvaluateChunk(int first, int last, bool jacobians, Accumulator& sum) const {
  sum.ok = true;
  sum.cost = 0;
  sum.group = -1;
  if (jacobians) {
    sum.H.setZero(tangent_size_, tangent_size_);
    sum.g.setZero(tangent_size_);
  }
  double plus_jacobian[7 * 6];
  for (int index = first; index < last; ++index) {
    // Every residual block's cost and loss is a heap object of its own, and a window holds tens of
    // thousands (one per LiDAR point): fetched only when used, each block waited on memory for them
    // (perf: the first reads of the two took 60 % of this function's own time).
    if (index + kPrefetchAhead < last) {
      const ResidualBlock& ahead = residuals_[index + kPrefetchAhead];
      for (int line = 0; line < kPrefetchCostLines; ++line)
        __builtin_prefetch(reinterpret_cast<const char*>(ahead.cost) + 64 * line);
      if (ahead.loss != nullptr) __builtin_prefetch(ahead.loss);
    }
    const ResidualBlock& block = residuals_[index];
    const int m = block.cost->num_residuals();
    const int local_size = block.local_size;
    const std::vector<int32_t>& sizes = block.cost->parameter_block_sizes();
    const int* local_offset = &local_offset_[block.first_param];
    const int* free = &free_[block.first_param];
    sum.residual.resize(m);
    sum.jacobian_pointers.assign(block.num_params, nullptr);
    const bool want = jacobians && local_size > 0;
    double* const* parameters = &params_[block.first_param];
    double* r = sum.residual.data();
    // J, row-major m x local_size.
    sum.J.resize(static_cast<std::size_t>(m) * std::max(local_size, 1));
    double* J = sum.J.data();
    if (!want) {
      if (!block.cost->Evaluate(parameters, r, nullptr)) {
        sum.ok = false;
        return;
      }
    } else if (block.tangent != nullptr) {
      // Direct tangent Jacobians, one m x t_p buffer per free block, then interleaved into J.
      sum.tangent_columns.resize(static_cast<std::size_t>(m) * local_size);
      for (int p = 0; p < block.num_params; ++p)
        if (local_offset[p] >= 0) sum.jacobian_pointers[p] = sum.tangent_columns.data() + m * local_offset[p];
      if (!block.tangent->EvaluateTangent(parameters, r, sum.jacobian_pointers.data())) {
        sum.ok = false;
        return;
      }
      for (int p = 0; p < block.num_params; ++p) {
        if (local_offset[p] < 0) continue;
        const int t = blocks_[free[p]].tangent_size;
        for (int k = 0; k < m; ++k)
          for (int c = 0; c < t; ++c)
            J[k * local_size + local_offset[p] + c] = sum.jacobian_pointers[p][k * t + c];
      }
    } else {
      // Ambient Jacobians (Ceres' convention), times PlusJacobian for pose blocks.
      int ambient_total = 0;
      for (int p = 0; p < block.num_params; ++p)
        if (local_offset[p] >= 0) ambient_total += sizes[p];
      sum.tangent_columns.resize(static_cast<std::size_t>(m) * ambient_total);
      int at = 0;
      for (int p = 0; p < block.num_params; ++p) {
        if (local_offset[p] < 0) continue;
        sum.jacobian_pointers[p] = sum.tangent_columns.data() + at;
        at += m * sizes[p];
      }
      if (!block.cost->Evaluate(parameters, r, sum.jacobian_pointers.data())) {
        sum.ok = false;
        return;
      }
      for (int p = 0; p < block.num_params; ++p) {
        if (local_offset[p] < 0) continue;
        const Block& free_block = blocks_[free[p]];
        const double* A = sum.jacobian_pointers[p];  // m x ambient, row-major
        if (free_block.pose) PoseManifold().PlusJacobian(free_block.data, plus_jacobian);
        for (int k = 0; k < m; ++k) {
          for (int c = 0; c < free_block.tangent_size; ++c) {
            double v = 0;
            if (free_block.pose) {
              for (int a = 0; a < 7; ++a) v += A[k * 7 + a] * plus_jacobian[a * 6 + c];
            } else {
              v = A[k * free_block.ambient_size + c];
            }
            J[k * local_size + local_offset[p] + c] = v;
          }
        }
      }
    }
    double s = 0;
    for (int k = 0; k < m; ++k) {
      if (!std::isfinite(r[k])) {
        sum.ok = false;
        return;
      }
      s += r[k] * r[k];
    }
    if (want)
      for (int e = 0; e < m * local_size; ++e)
        if (!std::isfinite(J[e])) {
          sum.ok = false;
          return;
        }
    if (block.loss == nullptr) {
      sum.cost += 0.5 * s;
    } else {
      double rho[3];
      block.loss->Evaluate(s, rho);
      sum.cost += 0.5 * rho[0];
      if (want) {
        // Ceres' Corrector: r <- sqrt(rho') / (1 - alpha) r, J <- sqrt(rho') (I - alpha r r^T / s) J with
        // alpha the smaller root of 1/2 alpha^2 - alpha - rho'' s / rho' = 0 (0 when rho'' <= 0).
        const double sqrt_rho1 = std::sqrt(std::max(rho[1], 0.0));
        if (s == 0.0 || rho[2] <= 0.0 || rho[1] <= 0.0) {
          for (int k = 0; k < m; ++k) r[k] *= sqrt_rho1;
          for (int e = 0; e < m * local_size; ++e) J[e] *= sqrt_rho1;
        } else {
          const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
          Eigen::Map<Eigen::VectorXd> rv(r, m);
          Eigen::Map<RowMajorMatrix> Jm(J, m, local_size);
          const Eigen::RowVectorXd rTJ = rv.transpose() * Jm;
          Jm = sqrt_rho1 * (Jm - (alpha / s) * rv * rTJ);
          rv *= sqrt_rho1 / (1.0 - alpha);
        }
      }
    }
    if (!want) continue;
    if (block.group != sum.group) {
      FlushGroup(sum);
      sum.group = block.group;
      sum.group_first = index;
      sum.group_H.setZero(local_size, local_size);
      sum.group_g.setZero(local_size);
      sum.group_H12.setZero();
      sum.group_g12.setZero();
    }
    if (m == 1 && local_size == 12) {  // the point-to-plane factor on a scan's begin and end poses
      const Eigen::Map<const Eigen::Matrix<double, 12, 1>> j(J);
      sum.group_H12.noalias() += j * j.transpose();
      sum.group_g12 += r[0] * j;
    } else {
      const Eigen::Map<const RowMajorMatrix> Jm(J, m, local_size);
      const Eigen::Map<const Eigen::VectorXd> rv(r, m);
      sum.group_H.noalias() += Jm.transpose() * Jm;
      sum.group_g.noalias() += Jm.transpose() * rv;
    }
  }
  if (jacobians) FlushGroup(sum);
}

// Adds the local system of the current group (its free blocks side by side) into the chunk's H and g.
void DenseLeastSquares::FlushGroup(Accumulator& sum) const {
  if (sum.group < 0) return;
  const ResidualBlock& block = residuals_[sum.group_first];
  if (block.local_size == 12) {
    sum.group_H += sum.group_H12;
    sum.group_g += sum.group_g12;
  }
  const int* free = &free_[block.first_param];
  const int* local_offset = &local_offset_[block.first_param];
  for (int p = 0; p < block.num_params; ++p) {
    if (local_offset[p] < 0) continue;
    const Block& bp = blocks_[free[p]];
    sum.g.segment(bp.offset, bp.tangent_size) += sum.group_g.segment(local_offset[p], bp.tangent_size);
    for (int q = 0; q < block.num_params; ++q) {
      if (local_offset[q] < 0) continue;
      const Block& bq = blocks_[free[q]];
      sum.H.block(bp.offset, bq.offset, bp.tangent_size, bq.tangent_size) +=
          sum.group_H.block(local_offset[p], local_offset[q], bp.tangent_size, bq.tangent_size);
    }
  }
  sum.group = -1;
}

void DenseLeastSquares::Plus(const Eigen::VectorXd& dx) {
  double out[7];
  for (const Block& block : blocks_) {
    if (block.pose) {
      PoseManifold().Plus(block.data, dx.data() + block.offset, out);
      std::copy(out, out + 7, block.data);
    } else {
      for (int k = 0; k < block.tangent_size; ++k) block.data[k] += dx[block.offset + k];
    }
  }
}

std::vector<double> DenseLeastSquares::SaveValues() const {
  std::vector<double> values;
  for (const Block& block : blocks_) values.insert(values.end(), block.data, block.data + block.ambient_size);
  return values;
}

void DenseLeastSquares::RestoreValues(const std::vector<double>& values) {
  std::size_t at = 0;
  for (const Block& block : blocks_) {
    std::copy(values.begin() + at, values.begin() + at + block.ambient_size, block.data);
    at += block.ambient_size;
  }
}

DenseSolverSummary DenseLeastSquares::Solve(const DenseSolverOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  DenseSolverSummary summary;
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  double cost = 0;
  if (!Evaluate(&cost, &H, &g)) return summary;
  summary.iterations = 1;
  summary.initial_cost = summary.final_cost = cost;
  summary.usable = true;
  if (tangent_size_ == 0) return summary;
  double mu = options.initial_mu, v = 2.0;
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  for (int step = 0; step < options.max_iterations; ++step) {
    if (g.lpNorm<Eigen::Infinity>() <= options.gradient_tolerance) {
      summary.converged = true;
      break;
    }
    if (std::chrono::duration<double>(Clock::now() - start).count() > options.max_time_s) break;
    Eigen::MatrixXd A = H;
    A.diagonal() += mu * H.diagonal().cwiseMax(kMinDiagonal);
    ldlt.compute(A);
    const Eigen::VectorXd dx = ldlt.solve(-g);
    ++summary.iterations;
    if (ldlt.info() != Eigen::Success || !dx.allFinite()) {
      mu *= v;
      v *= 2;
      continue;
    }
    const std::vector<double> before = SaveValues();
    const double x_norm = Eigen::Map<const Eigen::VectorXd>(before.data(), before.size()).norm();
    if (dx.norm() <= options.parameter_tolerance * (x_norm + options.parameter_tolerance)) {
      summary.converged = true;
      break;
    }
    // Decrease of the quadratic model: L(0) - L(dx) = -(g^T dx + 1/2 dx^T H dx).
    const double model_decrease = -(g.dot(dx) + 0.5 * dx.dot(H * dx));
    Plus(dx);
    double new_cost = 0;
    const bool evaluated = Evaluate(&new_cost, nullptr, nullptr);
    const double relative = evaluated && model_decrease > 0 ? (cost - new_cost) / model_decrease : -1.0;
    if (relative <= kMinRelativeDecrease) {
      RestoreValues(before);
      mu *= v;
      v *= 2;
      continue;
    }
    mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * relative - 1.0, 3));
    v = 2.0;
    // Converged: stop without linearizing again (the most expensive part of an iteration).
    if (cost - new_cost <= options.function_tolerance * cost) {
      cost = new_cost;
      summary.converged = true;
      break;
    }
    if (!Evaluate(&cost, &H, &g)) {  // cannot happen after a finite cost evaluation, unless J is not finite
      RestoreValues(before);
      Evaluate(&cost, &H, &g);
      break;
    }
  }
  summary.final_cost = cost;
  return summary;
}

}  // namespace uf::estimator
