// Gradients of the SH colour (splat/cpu_reference/spherical_harmonics.h) with respect to its coefficients
// and to the viewing direction, for the CPU reference backward pass.
#pragma once

#include <Eigen/Core>

namespace uf::splat {

// The 16 real SH basis values Y_k(d) (3DGS constants, the same polynomial as EvaluateSh) and their
// derivatives dY_k/d(x, y, z), taking x, y, z of the direction as independent variables (the
// normalization d = v / |v| is chained by the caller).
void ShBasisWithGradient(const Eigen::Vector3f& direction, float basis[16],
                         Eigen::Vector3f basis_gradient[16]);

// Backward of colour_c = sum_k c_kc Y_k(d) (before the +0.5 and the clamp) for degree `degree`:
// ADDS dL/dc_kc = Y_k(d) dL/dcolour_c to coefficient_gradients (coefficient-major, (degree + 1)^2 * 3)
// and returns dL/dd = sum_c dL/dcolour_c sum_k c_kc dY_k/dd.
Eigen::Vector3f ShBackward(int degree, const float* coefficients, const Eigen::Vector3f& direction,
                           const Eigen::Vector3f& dL_dcolour, float* coefficient_gradients);

}  // namespace uf::splat
