#include "splat/cpu_reference/spherical_harmonics.h"

#include <cassert>

#include "splat/gaussian_model.h"

namespace uf::splat {

void ShBasis(const Eigen::Vector3f& direction, float basis[16]) {
  // Evaluated in the same order as shaders/project_gaussians.comp.
  const float x = direction.x(), y = direction.y(), z = direction.z();
  const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  basis[0] = kShC0;
  basis[1] = -kShC1 * y;
  basis[2] = kShC1 * z;
  basis[3] = -kShC1 * x;
  basis[4] = kShC2[0] * xy;
  basis[5] = kShC2[1] * yz;
  basis[6] = kShC2[2] * (2.0f * zz - xx - yy);
  basis[7] = kShC2[3] * xz;
  basis[8] = kShC2[4] * (xx - yy);
  basis[9] = kShC3[0] * y * (3.0f * xx - yy);
  basis[10] = kShC3[1] * xy * z;
  basis[11] = kShC3[2] * y * (4.0f * zz - xx - yy);
  basis[12] = kShC3[3] * z * (2.0f * zz - 3.0f * xx - 3.0f * yy);
  basis[13] = kShC3[4] * x * (4.0f * zz - xx - yy);
  basis[14] = kShC3[5] * z * (xx - yy);
  basis[15] = kShC3[6] * x * (xx - 3.0f * yy);
}

Eigen::Vector3f EvaluateSh(int degree, const float* coefficients, const Eigen::Vector3f& direction) {
  assert(degree >= 0 && degree <= kMaxShDegree);
  float basis[16];
  ShBasis(direction, basis);
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();
  for (int k = 0; k < ShCoefficientsPerChannel(degree); ++k)
    for (int c = 0; c < 3; ++c) colour[c] += basis[k] * coefficients[k * 3 + c];
  return colour;
}

}  // namespace uf::splat
