#include "odometry/estimator/factors/gnss_offset_factor.h"

#include <ceres/autodiff_cost_function.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace uf::estimator {
namespace {

using Matrix33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// r_i = (next_i - a prev_i) w_i, w_i = 1 / (s_i sqrt(1 - a^2)).
struct OffsetProcessResidual {
  double a;
  Eigen::Vector3d weight;
  template <typename T>
  bool operator()(const T* previous, const T* next, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (next[i] - a * previous[i]) * weight[i];
    return true;
  }
};

// r_i = b_i w_i, w_i = 1 / s_i.
struct OffsetPriorResidual {
  Eigen::Vector3d weight;
  template <typename T>
  bool operator()(const T* offset, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = offset[i] * weight[i];
    return true;
  }
};

[[maybe_unused]] bool ValidSigmas(const Eigen::Vector3d& sigma) {
  return sigma.allFinite() && (sigma.array() > 0).all();
}

}  // namespace

GnssOffsetFactor::GnssOffsetFactor(std::unique_ptr<ceres::CostFunction> fix_factor,
                                   const Eigen::Matrix3d& white_covariance, GnssAxes axes)
    : fix_factor_(std::move(fix_factor)),
      fix_tangent_(dynamic_cast<const TangentJacobianCost*>(fix_factor_.get())),
      sqrt_information_(GnssSqrtInformation(white_covariance, axes)),
      offset_index_(static_cast<int>(fix_factor_->parameter_block_sizes().size())) {
  assert(fix_tangent_ != nullptr && fix_factor_->num_residuals() == 3);
  set_num_residuals(3);
  *mutable_parameter_block_sizes() = fix_factor_->parameter_block_sizes();
  mutable_parameter_block_sizes()->push_back(kGnssOffsetSize);
}

bool GnssOffsetFactor::Evaluate(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  if (!fix_factor_->Evaluate(parameters, residuals, jacobians)) return false;
  AddOffset(parameters, residuals, jacobians);
  return true;
}

bool GnssOffsetFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                       double** tangent_jacobians) const {
  if (!fix_tangent_->EvaluateTangent(parameters, residuals, tangent_jacobians)) return false;
  AddOffset(parameters, residuals, tangent_jacobians);
  return true;
}

// The offset's part, the same in the ambient and the tangent form: r += L_w b, dr/db = L_w.
void GnssOffsetFactor::AddOffset(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  Eigen::Map<Eigen::Vector3d>(residuals) +=
      sqrt_information_ * Eigen::Map<const Eigen::Vector3d>(parameters[offset_index_]);
  if (jacobians == nullptr || jacobians[offset_index_] == nullptr) return;
  Eigen::Map<Matrix33> J(jacobians[offset_index_]);
  J = sqrt_information_;
}

std::unique_ptr<ceres::CostFunction> MakeGnssOffsetProcessFactor(double dt_s, double tau_s,
                                                                 const Eigen::Vector3d& sigma_m) {
  assert(dt_s > 0 && tau_s > 0 && ValidSigmas(sigma_m));
  const double a = std::exp(-dt_s / tau_s);
  // 1 - a^2 ~ 2 dt / tau for close nodes; the floor only keeps a zero dt (asserted out) finite.
  const double innovation = std::sqrt(std::max(1.0 - a * a, 1e-12));
  return std::make_unique<ceres::AutoDiffCostFunction<OffsetProcessResidual, 3, 3, 3>>(
      new OffsetProcessResidual{a, (sigma_m * innovation).cwiseInverse()});
}

std::unique_ptr<ceres::CostFunction> MakeGnssOffsetPrior(const Eigen::Vector3d& sigma_m) {
  assert(ValidSigmas(sigma_m));
  return std::make_unique<ceres::AutoDiffCostFunction<OffsetPriorResidual, 3, 3>>(
      new OffsetPriorResidual{sigma_m.cwiseInverse()});
}

}  // namespace uf::estimator
