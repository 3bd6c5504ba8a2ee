// Rotation of the view-dependent colour of a Gaussian: real spherical harmonics coefficients (3DGS basis,
// degrees 1..3, see gaussian_model.h) re-expressed after a rotation R of the scene.
//
// A Gaussian whose colour is f(d) = sum_k c_k Y_k(d) (d the unit viewing direction, world frame), moved
// with the scene by a rotation R (x' = R x), shows in direction d' the colour it showed in R^T d':
//   f'(d') = f(R^T d')  =>  sum_k c'_k Y_k(d') = sum_k c_k Y_k(R^T d')  for all d'.
// Each degree l spans a rotation-invariant subspace, so c'_l = D_l c_l with a (2l+1) x (2l+1) matrix D_l
// (a Wigner D-matrix in this real basis). D_l is found by collocation: with A_ij = Y_lj(d_i) and
// B_ij = Y_lj(R^T d_i) at 64 well-spread directions d_i (Fibonacci sphere), A D_l = B holds exactly and is
// solved by QR in double precision. Degree 0 (the DC term) is invariant.
#pragma once

#include <Eigen/Core>
#include <array>

namespace uf::exporting {

// The 16 real SH basis functions of the 3DGS renderers (Condon-Shortley phase), at the unit vector d.
std::array<double, 16> ShBasis(const Eigen::Vector3d& d);

class ShRotation {
 public:
  explicit ShRotation(const Eigen::Matrix3d& R);

  // Rotates one Gaussian's coefficients in place; `sh` is coefficient-major (sh[k * 3 + c]) with
  // (degree + 1)^2 coefficients per channel.
  void Apply(float* sh, int degree) const;

 private:
  std::array<Eigen::MatrixXd, 4> blocks_;  // D_l for l = 0..3
};

}  // namespace uf::exporting
