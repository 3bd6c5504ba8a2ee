#include "odometry/estimator/window/dense_least_squares.h"

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
constexpr double kMinRelativeDecrease = 1e-3;  // a step must achieve this share of the model's decrease

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
  assert(cost != nullptr && blocks.size() == cost->parameter_block_sizes().size());
  residuals_.push_back({cost, dynamic_cast<const TangentJacobianCost*>(cost), loss,
                        static_cast<int>(params_.size()), static_cast<int>(blocks.size())});
  for (double* block : blocks) {
    params_.push_back(block);
    const auto it = block_of_.find(block);
    free_.push_back(it == block_of_.end() ? -1 : it->second);
  }
}

bool DenseLeastSquares::Linearize(double* cost, Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  return Evaluate(cost, H, g);
}

// F and, when H is given, the robustified normal equations (see the header). Each residual block's tangent
// Jacobian J (m x L, its free blocks side by side) is formed in scratch buffers; J^T J and J^T r are summed
// in a local L x L system while consecutive residual blocks act on the same free blocks, and scattered into
// H and g when that changes (FlushGroup).
bool DenseLeastSquares::Evaluate(double* cost, Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  const bool jacobians = H != nullptr;
  if (jacobians) {
    H->setZero(tangent_size_, tangent_size_);
    g->setZero(tangent_size_);
  }
  group_blocks_.clear();
  double total = 0;
  double plus_jacobian[7 * 6];
  for (const ResidualBlock& block : residuals_) {
    const int m = block.cost->num_residuals();
    const std::vector<int32_t>& sizes = block.cost->parameter_block_sizes();
    residual_.resize(m);
    jacobian_pointers_.assign(block.num_params, nullptr);
    local_offset_.assign(block.num_params, -1);
    int local_size = 0, ambient_total = 0;
    for (int p = 0; p < block.num_params && jacobians; ++p) {
      const int b = free_[block.first_param + p];
      if (b < 0) continue;
      local_offset_[p] = local_size;
      local_size += blocks_[b].tangent_size;
      ambient_total += sizes[p];
    }
    const bool want = jacobians && local_size > 0;
    double* const* parameters = &params_[block.first_param];
    double* r = residual_.data();
    // J, row-major m x local_size.
    tangent_.resize(static_cast<std::size_t>(m) * std::max(local_size, 1));
    double* J = tangent_.data();
    if (!want) {
      if (!block.cost->Evaluate(parameters, r, nullptr)) return false;
    } else if (block.tangent != nullptr) {
      // Direct tangent Jacobians, one m x t_p buffer per free block, then interleaved into J.
      ambient_.resize(static_cast<std::size_t>(m) * local_size);
      for (int p = 0; p < block.num_params; ++p)
        if (local_offset_[p] >= 0) jacobian_pointers_[p] = ambient_.data() + m * local_offset_[p];
      if (!block.tangent->EvaluateTangent(parameters, r, jacobian_pointers_.data())) return false;
      for (int p = 0; p < block.num_params; ++p) {
        if (local_offset_[p] < 0) continue;
        const int t = blocks_[free_[block.first_param + p]].tangent_size;
        for (int k = 0; k < m; ++k)
          for (int c = 0; c < t; ++c)
            J[k * local_size + local_offset_[p] + c] = jacobian_pointers_[p][k * t + c];
      }
    } else {
      // Ambient Jacobians (Ceres' convention), times PlusJacobian for pose blocks.
      ambient_.resize(static_cast<std::size_t>(m) * ambient_total);
      int at = 0;
      for (int p = 0; p < block.num_params; ++p) {
        if (local_offset_[p] < 0) continue;
        jacobian_pointers_[p] = ambient_.data() + at;
        at += m * sizes[p];
      }
      if (!block.cost->Evaluate(parameters, r, jacobian_pointers_.data())) return false;
      for (int p = 0; p < block.num_params; ++p) {
        if (local_offset_[p] < 0) continue;
        const Block& free_block = blocks_[free_[block.first_param + p]];
        const double* A = jacobian_pointers_[p];  // m x ambient, row-major
        if (free_block.pose) PoseManifold().PlusJacobian(free_block.data, plus_jacobian);
        for (int k = 0; k < m; ++k) {
          for (int c = 0; c < free_block.tangent_size; ++c) {
            double v = 0;
            if (free_block.pose) {
              for (int a = 0; a < 7; ++a) v += A[k * 7 + a] * plus_jacobian[a * 6 + c];
            } else {
              v = A[k * free_block.ambient_size + c];
            }
            J[k * local_size + local_offset_[p] + c] = v;
          }
        }
      }
    }
    double s = 0;
    for (int k = 0; k < m; ++k) {
      if (!std::isfinite(r[k])) return false;
      s += r[k] * r[k];
    }
    if (want)
      for (int e = 0; e < m * local_size; ++e)
        if (!std::isfinite(J[e])) return false;
    if (block.loss == nullptr) {
      total += 0.5 * s;
    } else {
      double rho[3];
      block.loss->Evaluate(s, rho);
      total += 0.5 * rho[0];
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
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jm(J, m,
                                                                                                local_size);
          const Eigen::RowVectorXd rTJ = rv.transpose() * Jm;
          Jm = sqrt_rho1 * (Jm - (alpha / s) * rv * rTJ);
          rv *= sqrt_rho1 / (1.0 - alpha);
        }
      }
    }
    if (!want) continue;
    // Consecutive residual blocks on the same free blocks (one scan's points) share one local system.
    group_key_.clear();
    for (int p = 0; p < block.num_params; ++p)
      if (local_offset_[p] >= 0) group_key_.push_back(free_[block.first_param + p]);
    if (group_key_ != group_blocks_) {
      FlushGroup(H, g);
      group_blocks_ = group_key_;
      group_size_ = local_size;
      group_H_.setZero(local_size, local_size);
      group_g_.setZero(local_size);
      group_H12_.setZero();
      group_g12_.setZero();
    }
    if (m == 1 && local_size == 12) {  // the point-to-plane factor on a scan's begin and end poses
      const Eigen::Map<const Eigen::Matrix<double, 12, 1>> j(J);
      group_H12_.noalias() += j * j.transpose();
      group_g12_ += r[0] * j;
    } else {
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jm(
          J, m, local_size);
      const Eigen::Map<const Eigen::VectorXd> rv(r, m);
      group_H_.noalias() += Jm.transpose() * Jm;
      group_g_.noalias() += Jm.transpose() * rv;
    }
  }
  if (!std::isfinite(total)) return false;
  if (jacobians) FlushGroup(H, g);
  *cost = total;
  return true;
}

// Adds the local system of the current group (its free blocks side by side) into H and g.
void DenseLeastSquares::FlushGroup(Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  if (group_blocks_.empty()) return;
  if (group_size_ == 12) {
    group_H_ += group_H12_;
    group_g_ += group_g12_;
  }
  int lp = 0;
  for (const int bp : group_blocks_) {
    const Block& p = blocks_[bp];
    g->segment(p.offset, p.tangent_size) += group_g_.segment(lp, p.tangent_size);
    int lq = 0;
    for (const int bq : group_blocks_) {
      const Block& q = blocks_[bq];
      H->block(p.offset, q.offset, p.tangent_size, q.tangent_size) +=
          group_H_.block(lp, lq, p.tangent_size, q.tangent_size);
      lq += q.tangent_size;
    }
    lp += p.tangent_size;
  }
  group_blocks_.clear();
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
