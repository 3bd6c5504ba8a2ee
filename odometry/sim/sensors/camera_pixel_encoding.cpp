#include "odometry/sim/sensors/camera_pixel_encoding.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace uf::sim {
namespace {

double SrgbEncode(double x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055; }

// Inverse of the standard normal CDF, Phi^-1(p) for p in (0, 1): Acklam's rational approximation
// (relative error 1.2e-9), then one Halley step on Phi(x) - p with Phi(x) = erfc(-x / sqrt(2)) / 2, which
// brings it to double precision.
double InverseNormalCdf(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155633180e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  constexpr double p_low = 0.02425;
  double x = 0.0;
  if (p < p_low || p > 1.0 - p_low) {
    const double q = std::sqrt(-2.0 * std::log(p < p_low ? p : 1.0 - p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    if (p > 1.0 - p_low) x = -x;
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // Halley: e = Phi(x) - p, u = e / phi(x) with phi(x) = exp(-x^2/2) / sqrt(2 pi); x -= u / (1 + x u / 2).
  const double e = 0.5 * std::erfc(-x / std::numbers::sqrt2) - p;
  const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

const std::vector<float>& SrgbTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(kSrgbTableSteps + 2);
    for (int i = 0; i <= kSrgbTableSteps; ++i)
      t[i] = static_cast<float>(255.0 * SrgbEncode(double(i) / kSrgbTableSteps));
    t[kSrgbTableSteps + 1] = t[kSrgbTableSteps];  // guard for the interpolation at x = 1
    return t;
  }();
  return table;
}

const std::vector<float>& NormalTable() {
  static const std::vector<float> table = [] {
    constexpr int kCount = 65536;
    std::vector<double> x(kCount);
    double sum_squares = 0.0;
    for (int i = 0; i < kCount; ++i) {
      x[i] = InverseNormalCdf((i + 0.5) / kCount);
      sum_squares += x[i] * x[i];
    }
    const double scale = 1.0 / std::sqrt(sum_squares / kCount);  // the mean is 0 by symmetry
    std::vector<float> t(kCount);
    for (int i = 0; i < kCount; ++i) t[i] = static_cast<float>(x[i] * scale);
    return t;
  }();
  return table;
}

}  // namespace

const float* SrgbDnTable() { return SrgbTable().data(); }
const float* StandardNormalTable() { return NormalTable().data(); }

}  // namespace uf::sim
