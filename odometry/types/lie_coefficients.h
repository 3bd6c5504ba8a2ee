// Scalar coefficients of the SO(3)/SE(3) closed forms, as functions of the rotation angle theta >= 0.
// Each one has a removable singularity at theta = 0 where the closed form loses digits to cancellation;
// below a threshold the Taylor series is used instead. Thresholds are chosen so that both branches are
// accurate to ~1e-13 relative at the switch (series truncation error vs. cancellation error eps / theta^k).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace uf::lie {

// Below this angle the coefficients whose closed forms need sin take their series to the theta^14 term,
// which leaves a truncation below 1e-19 relative at 0.5: exact in doubles, and no libm call on the paths
// that evaluate them per LiDAR point (a sweep turns by a fraction of this).
inline constexpr double kSeriesBelow = 0.5;

// 1 - x / d_0 (1 - x / d_1 (1 - ... (1 - x / d_last))): an alternating series whose k-th term is the one
// before times x / d_k, summed innermost first.
template <std::size_t N>
inline double AlternatingSeries(double x, const std::array<double, N>& d) {
  double sum = 1.0;
  for (std::size_t k = N; k-- > 0;) sum = 1.0 - x / d[k] * sum;
  return sum;
}

// sin(theta) / theta = 1 - theta^2/3! + theta^4/5! - ...: the ratios (2k)(2k+1), k = 1..7.
inline double SinOverTheta(double theta) {
  if (theta < kSeriesBelow)
    return AlternatingSeries(theta * theta, std::array{6.0, 20.0, 42.0, 72.0, 110.0, 156.0, 210.0});
  return std::sin(theta) / theta;
}

// (1 - cos(theta)) / theta^2 = 2 sin^2(theta/2) / theta^2 = 0.5 (sin(h)/h)^2 with h = theta/2: no
// cancellation.
inline double OneMinusCosOverTheta2(double theta) {
  const double s = SinOverTheta(0.5 * theta);
  return 0.5 * s * s;
}

// (theta - sin(theta)) / theta^3 = 1/3! - theta^2/5! + ...: 1/6 and the ratios (2k+2)(2k+3), k = 1..7.
inline double ThetaMinusSinOverTheta3(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesBelow)
    return AlternatingSeries(t2, std::array{20.0, 42.0, 72.0, 110.0, 156.0, 210.0, 272.0}) / 6.0;
  return (theta - std::sin(theta)) / (t2 * theta);
}

// 1/theta^2 - (1 + cos(theta)) / (2 theta sin(theta)) = 1/theta^2 - cot(theta/2) / (2 theta)
//   = 1/12 + theta^2/720 + theta^4/30240 + theta^6/1209600 + ...   (the K^2 coefficient of Jl^-1)
inline double JacobianInverseCoefficient(double theta) {
  const double t2 = theta * theta;
  if (theta < 0.1) return 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1209600.0;
  const double half = 0.5 * theta;
  return 1.0 / t2 - std::cos(half) / (std::sin(half) * 2.0 * theta);
}

// (theta^2/2 + cos(theta) - 1) / theta^4 = 1/24 - theta^2/720 + theta^4/40320 - theta^6/3628800 + ...
inline double CosCoefficientQ(double theta) {
  const double t2 = theta * theta;
  if (theta < 0.5) {
    return 1.0 / 24.0 - t2 / 720.0 + t2 * t2 / 40320.0 - t2 * t2 * t2 / 3628800.0 +
           t2 * t2 * t2 * t2 / 479001600.0;
  }
  return (0.5 * t2 + std::cos(theta) - 1.0) / (t2 * t2);
}

// (theta - sin(theta) - theta^3/6) / theta^5 = -1/120 + theta^2/5040 - theta^4/362880 + theta^6/39916800 -
// ...
inline double SinCoefficientQ(double theta) {
  const double t2 = theta * theta;
  if (theta < 0.5) {
    return -1.0 / 120.0 + t2 / 5040.0 - t2 * t2 / 362880.0 + t2 * t2 * t2 / 39916800.0 -
           t2 * t2 * t2 * t2 / 6227020800.0;
  }
  return (theta - std::sin(theta) - t2 * theta / 6.0) / (t2 * t2 * theta);
}

}  // namespace uf::lie
