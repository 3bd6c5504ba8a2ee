// What the marginalization tests share: the dense tangent Jacobian and residual of a Ceres problem.
#pragma once

#include <ceres/problem.h>

#include <Eigen/Dense>
#include <vector>

namespace uf::estimator::testing {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

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
