#include "splat/cpu_reference/spherical_harmonics_backward.h"

#include <cassert>

#include "splat/cpu_reference/spherical_harmonics.h"
#include "splat/gaussian_model.h"

namespace uf::splat {

void ShBasisWithGradient(const Eigen::Vector3f& direction, float basis[16],
                         Eigen::Vector3f basis_gradient[16]) {
  const float x = direction.x(), y = direction.y(), z = direction.z();
  const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  ShBasis(direction, basis);
  // The partial derivatives (d/dx, d/dy, d/dz) of each Y_k's polynomial.
  basis_gradient[0] = {0, 0, 0};
  basis_gradient[1] = {0, -kShC1, 0};
  basis_gradient[2] = {0, 0, kShC1};
  basis_gradient[3] = {-kShC1, 0, 0};
  basis_gradient[4] = kShC2[0] * Eigen::Vector3f(y, x, 0);
  basis_gradient[5] = kShC2[1] * Eigen::Vector3f(0, z, y);
  basis_gradient[6] = kShC2[2] * Eigen::Vector3f(-2 * x, -2 * y, 4 * z);
  basis_gradient[7] = kShC2[3] * Eigen::Vector3f(z, 0, x);
  basis_gradient[8] = kShC2[4] * Eigen::Vector3f(2 * x, -2 * y, 0);
  // y (3xx - yy) = 3xxy - y^3
  basis_gradient[9] = kShC3[0] * Eigen::Vector3f(6 * xy, 3 * xx - 3 * yy, 0);
  basis_gradient[10] = kShC3[1] * Eigen::Vector3f(yz, xz, xy);
  // y (4zz - xx - yy) = 4yzz - xxy - y^3
  basis_gradient[11] = kShC3[2] * Eigen::Vector3f(-2 * xy, 4 * zz - xx - 3 * yy, 8 * yz);
  // z (2zz - 3xx - 3yy) = 2z^3 - 3xxz - 3yyz
  basis_gradient[12] = kShC3[3] * Eigen::Vector3f(-6 * xz, -6 * yz, 6 * zz - 3 * xx - 3 * yy);
  // x (4zz - xx - yy) = 4xzz - x^3 - xyy
  basis_gradient[13] = kShC3[4] * Eigen::Vector3f(4 * zz - 3 * xx - yy, -2 * xy, 8 * xz);
  // z (xx - yy)
  basis_gradient[14] = kShC3[5] * Eigen::Vector3f(2 * xz, -2 * yz, xx - yy);
  // x (xx - 3yy) = x^3 - 3xyy
  basis_gradient[15] = kShC3[6] * Eigen::Vector3f(3 * xx - 3 * yy, -6 * xy, 0);
}

Eigen::Vector3f ShBackward(int degree, const float* coefficients, const Eigen::Vector3f& direction,
                           const Eigen::Vector3f& dL_dcolour, float* coefficient_gradients) {
  assert(degree >= 0 && degree <= kMaxShDegree);
  float basis[16];
  Eigen::Vector3f basis_gradient[16];
  ShBasisWithGradient(direction, basis, basis_gradient);
  // colour_c = sum_k c_kc Y_k(d):  dL/dc_kc = Y_k dL/dcolour_c,  dL/dd = sum_k (sum_c c_kc dL/dcolour_c)
  // dY_k/dd.
  Eigen::Vector3f dL_ddirection = Eigen::Vector3f::Zero();
  for (int k = 0; k < ShCoefficientsPerChannel(degree); ++k) {
    float weight = 0;
    for (int c = 0; c < 3; ++c) {
      coefficient_gradients[k * 3 + c] += basis[k] * dL_dcolour[c];
      weight += coefficients[k * 3 + c] * dL_dcolour[c];
    }
    dL_ddirection += weight * basis_gradient[k];
  }
  return dL_ddirection;
}

}  // namespace uf::splat
