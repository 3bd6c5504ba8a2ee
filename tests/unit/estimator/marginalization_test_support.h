// What the marginalization and factor-graph tests share: a linear factor on Euclidean blocks, and the dense
// tangent Jacobian and residual of a Ceres problem.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/crs_matrix.h>
#include <ceres/problem.h>

#include <Eigen/Dense>
#include <utility>
#include <vector>

namespace uf::estimator::testing {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// r = (sum_i A_i x_i - z) / sigma on Euclidean blocks.
class LinearFactor : public ceres::CostFunction {
 public:
  LinearFactor(std::vector<Eigen::MatrixXd> A, Eigen::VectorXd z, double sigma)
      : A_(std::move(A)), z_(std::move(z)), sigma_(sigma) {
    set_num_residuals(static_cast<int>(z_.size()));
    for (const auto& a : A_) mutable_parameter_block_sizes()->push_back(static_cast<int>(a.cols()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::VectorXd r = -z_;
    for (size_t i = 0; i < A_.size(); ++i) r += A_[i] * Eigen::Map<const Eigen::VectorXd>(x[i], A_[i].cols());
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r / sigma_;
    for (size_t i = 0; jacobians != nullptr && i < A_.size(); ++i) {
      if (jacobians[i]) Eigen::Map<RowMajorMatrix>(jacobians[i], A_[i].rows(), A_[i].cols()) = A_[i] / sigma_;
    }
    return true;
  }
  std::vector<Eigen::MatrixXd> A_;
  Eigen::VectorXd z_;
  double sigma_;
};

// Dense tangent Jacobian and residual of a problem over the given blocks (Problem::Evaluate uses tangents).
inline void EvaluateDense(ceres::Problem& problem, const std::vector<double*>& blocks, Eigen::MatrixXd& J,
                          Eigen::VectorXd& r) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = blocks;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  problem.Evaluate(options, nullptr, &residuals, nullptr, &crs);
  J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) J(row, crs.cols[k]) = crs.values[k];
  }
  r = Eigen::Map<Eigen::VectorXd>(residuals.data(), residuals.size());
}

}  // namespace uf::estimator::testing
