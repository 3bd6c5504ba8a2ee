// Central-difference Jacobians for the analytic-Jacobian tests. With step h the truncation error is
// O(h^2 * f''') and the rounding error O(eps * |f| / h). Lie-group functions are O(1): h = 1e-6 gives
// ~1e-10, compared with a tolerance of 1e-8. Projections are ~1e3 px of points ~1 m away: h = 1e-5 m gives
// ~2e-8 px/m rounding and ~1e-7 px/m truncation error, compared with a tolerance of 1e-5 px/m.
#pragma once

#include <Eigen/Core>

namespace uf::test {

// J(:, i) = (f(x + h e_i) - f(x - h e_i)) / (2 h), for f : R^N -> R^M.
template <int M, int N, typename Function>
Eigen::Matrix<double, M, N> NumericJacobian(Function f, const Eigen::Matrix<double, N, 1>& x,
                                            double h = 1e-6) {
  Eigen::Matrix<double, M, N> J;
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> plus = x, minus = x;
    plus(i) += h;
    minus(i) -= h;
    J.col(i) = (f(plus) - f(minus)) / (2.0 * h);
  }
  return J;
}

}  // namespace uf::test
