// The pose parameter block's manifold for Ceres (see nav_state.h): ambient {t, q} (7), tangent [dt; dtheta]
// (6), Plus(x, delta) = {t + dt, q * Exp(dtheta)} (right-multiplicative rotation update).
#pragma once

#include <ceres/manifold.h>

#include <Eigen/Core>

namespace uf::estimator {

class PoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  // d Plus(x, delta) / d delta at delta = 0 (7x6, row-major): [[I, 0], [0, d(q Exp(w))/dw at 0]], the
  // latter = 1/2 [q]_L [0; I] in the (x, y, z, w) quaternion layout.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  // Minus(y, x) = [t_y - t_x; Log(q_x^-1 q_y)].
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// Analytic factors derive residuals with respect to the tangent [dt; dtheta]. Ceres wants the Jacobian with
// respect to the ambient block (rows x 7, row-major) and multiplies it by PlusJacobian. This writes
// J_ambient = J_tangent * MinusJacobian(pose), so that J_ambient * PlusJacobian(pose) = J_tangent exactly
// (MinusJacobian is the pseudo-inverse of PlusJacobian). Keeps the manifold's Jacobians true, so automatic
// and numeric differentiation of other factors stay valid.
void TangentToAmbientJacobian(const double* pose, const double* J_tangent, int rows, double* J_ambient);

}  // namespace uf::estimator
