// Real spherical harmonics up to degree 3 with the 3DGS constants and sign conventions (the same polynomial
// the projection shader evaluates), used to turn a Gaussian's SH coefficients into a colour.
#pragma once

#include <Eigen/Core>

namespace uf::splat {

// The 3DGS constants of the real SH basis, degrees 1-3 (C0 = kShC0 is in gaussian_model.h).
inline constexpr float kShC1 = 0.4886025119029199f;
inline constexpr float kShC2[5] = {1.0925484305920792f, -1.0925484305920792f, 0.31539156525252005f,
                                   -1.0925484305920792f, 0.5462742152960396f};
inline constexpr float kShC3[7] = {-0.5900435899266435f, 2.890611442640554f,   -0.4570457994644658f,
                                   0.3731763325901154f,  -0.4570457994644658f, 1.445305721320277f,
                                   -0.5900435899266435f};

// The 16 basis values Y_k(d) listed below, in the order of the coefficients.
void ShBasis(const Eigen::Vector3f& direction, float basis[16]);

// SH colour at the unit direction d (camera centre -> Gaussian mean), BEFORE the +0.5 offset and the clamp:
//   c = sum_{l <= degree} sum_m c_lm Y_lm(d), with (x, y, z) = d and
//   Y_0 = C0;  Y_1 = (-C1 y, C1 z, -C1 x);
//   Y_2 = (C2_0 xy, C2_1 yz, C2_2 (2zz - xx - yy), C2_3 xz, C2_4 (xx - yy));
//   Y_3 = (C3_0 y (3xx - yy), C3_1 xyz, C3_2 y (4zz - xx - yy), C3_3 z (2zz - 3xx - 3yy),
//          C3_4 x (4zz - xx - yy), C3_5 z (xx - yy), C3_6 x (xx - 3yy)).
// coefficients: coefficient-major (coefficient k of channel c at [k * 3 + c]), (degree + 1)^2 * 3 values.
Eigen::Vector3f EvaluateSh(int degree, const float* coefficients, const Eigen::Vector3f& direction);

}  // namespace uf::splat
