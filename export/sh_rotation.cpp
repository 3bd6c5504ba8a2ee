#include "export/sh_rotation.h"

#include <Eigen/QR>
#include <cmath>
#include <numbers>

namespace uf::exporting {

std::array<double, 16> ShBasis(const Eigen::Vector3d& d) {
  // Constants and signs as in the 3DGS reference renderer and the KHR_gaussian_splatting text.
  constexpr double kC0 = 0.28209479177387814, kC1 = 0.4886025119029199;
  constexpr double kC2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                             -1.0925484305920792, 0.5462742152960396};
  constexpr double kC3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                             -0.4570457994644658, 1.445305721320277, -0.5900435899266435};
  const double x = d.x(), y = d.y(), z = d.z();
  const double xx = x * x, yy = y * y, zz = z * z;
  return {kC0,
          -kC1 * y,
          kC1 * z,
          -kC1 * x,
          kC2[0] * x * y,
          kC2[1] * y * z,
          kC2[2] * (2 * zz - xx - yy),
          kC2[3] * x * z,
          kC2[4] * (xx - yy),
          kC3[0] * y * (3 * xx - yy),
          kC3[1] * x * y * z,
          kC3[2] * y * (4 * zz - xx - yy),
          kC3[3] * z * (2 * zz - 3 * xx - 3 * yy),
          kC3[4] * x * (4 * zz - xx - yy),
          kC3[5] * z * (xx - yy),
          kC3[6] * x * (xx - 3 * yy)};
}

ShRotation::ShRotation(const Eigen::Matrix3d& R) {
  constexpr int kSamples = 64;
  Eigen::MatrixXd A(kSamples, 16), B(kSamples, 16);
  for (int i = 0; i < kSamples; ++i) {
    // Fibonacci sphere: z uniform in (-1, 1), azimuth advancing by the golden angle.
    const double z = 1.0 - (2.0 * i + 1.0) / kSamples;
    const double r = std::sqrt(1.0 - z * z), phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0));
    const Eigen::Vector3d d(r * std::cos(phi), r * std::sin(phi), z);
    const std::array<double, 16> a = ShBasis(d), b = ShBasis(R.transpose() * d);
    for (int k = 0; k < 16; ++k) {
      A(i, k) = a[k];
      B(i, k) = b[k];
    }
  }
  for (int l = 0; l <= 3; ++l) {
    const int first = l * l, n = 2 * l + 1;
    blocks_[l] = A.middleCols(first, n).colPivHouseholderQr().solve(B.middleCols(first, n));
  }
}

void ShRotation::Apply(float* sh, int degree) const {
  for (int l = 1; l <= degree; ++l) {
    const int first = l * l, n = 2 * l + 1;
    const Eigen::MatrixXd& D = blocks_[l];
    for (int c = 0; c < 3; ++c) {
      double in[7], out[7] = {};
      for (int j = 0; j < n; ++j) in[j] = sh[(first + j) * 3 + c];
      for (int j = 0; j < n; ++j)
        for (int m = 0; m < n; ++m) out[m] += D(m, j) * in[j];
      for (int m = 0; m < n; ++m) sh[(first + m) * 3 + c] = static_cast<float>(out[m]);
    }
  }
}

}  // namespace uf::exporting
