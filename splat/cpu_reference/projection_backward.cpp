// The per-Gaussian part of the CPU reference backward: rules 1-2 (projection, EWA covariance, SH colour,
// opacity) backwards; declared in reference_backward.h. Recomputes the forward's intermediates in float,
// in the order of ProjectGaussian (reference_renderer.cpp).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "splat/cpu_reference/reference_backward.h"
#include "splat/cpu_reference/spherical_harmonics.h"
#include "splat/cpu_reference/spherical_harmonics_backward.h"

namespace uf::splat {

namespace {

// dL/dq of R(q) for a UNIT quaternion q = (w, x, y, z), given G = dL/dR, with
//   R = [[1 - 2(yy + zz), 2(xy - wz),     2(xz + wy)    ],
//        [2(xy + wz),     1 - 2(xx + zz), 2(yz - wx)    ],
//        [2(xz - wy),     2(yz + wx),     1 - 2(xx + yy)]]   (Eigen's toRotationMatrix).
Eigen::Vector4f RotationMatrixBackward(const Eigen::Quaternionf& q, const Eigen::Matrix3f& G) {
  const float w = q.w(), x = q.x(), y = q.y(), z = q.z();
  Eigen::Vector4f d;
  d[0] = 2 * (-z * G(0, 1) + y * G(0, 2) + z * G(1, 0) - x * G(1, 2) - y * G(2, 0) + x * G(2, 1));
  d[1] = 2 * (y * G(0, 1) + z * G(0, 2) + y * G(1, 0) - 2 * x * G(1, 1) - w * G(1, 2) + z * G(2, 0) +
              w * G(2, 1) - 2 * x * G(2, 2));
  d[2] = 2 * (-2 * y * G(0, 0) + x * G(0, 1) + w * G(0, 2) + x * G(1, 0) + z * G(1, 2) - w * G(2, 0) +
              z * G(2, 1) - 2 * y * G(2, 2));
  d[3] = 2 * (-2 * z * G(0, 0) - w * G(0, 1) + x * G(0, 2) + w * G(1, 0) - 2 * z * G(1, 1) + y * G(1, 2) +
              x * G(2, 0) + y * G(2, 1));
  return d;
}

}  // namespace

void ProjectGaussianBackward(const GaussianModel& model, std::size_t index, const FloatCamera& camera,
                             const RenderSettings& settings, const ProjectedGaussianGradients& upstream,
                             GaussianGradients* gradients) {
  const ProjectedGaussian g = ProjectGaussian(model, index, camera, settings);
  if (g.culled) return;
  const Eigen::Vector3f& mu = model.positions[index];
  const Eigen::Matrix3f& W = camera.R_camera_world;
  const Eigen::Vector3f t = W * mu + camera.t_camera_world;

  // Opacity o = sigmoid(l): do/dl = o (1 - o).
  gradients->opacity_logit[index] += upstream.opacity * g.opacity * (1.0f - g.opacity);

  // Colour = max(0, SH(d) + 0.5), d = v / |v|, v = mu - camera centre. No gradient through a clamped
  // channel; dd/dv = (I - d d^T) / |v|.
  const Eigen::Vector3f view = mu - camera.centre_world;
  const Eigen::Vector3f direction = view.normalized();
  const std::size_t stride = static_cast<std::size_t>(model.ShStride());
  const float* coefficients = model.sh.data() + index * stride;
  const Eigen::Vector3f raw = EvaluateSh(model.sh_degree, coefficients, direction).array() + 0.5f;
  Eigen::Vector3f dL_dcolour = upstream.color;
  for (int c = 0; c < 3; ++c)
    if (raw[c] < 0.0f) dL_dcolour[c] = 0.0f;
  const Eigen::Vector3f dL_ddirection =
      ShBackward(model.sh_degree, coefficients, direction, dL_dcolour, gradients->sh.data() + index * stride);
  Eigen::Vector3f dL_dmu = (dL_ddirection - direction * direction.dot(dL_ddirection)) / view.norm();

  // Conic Q = Sigma_2D^-1 stored (A, B, C) = (Q00, Q01, Q11). As a symmetric-matrix gradient
  // G_Q = [[gA, gB/2], [gB/2, gC]]; dQ = -Q dSigma_2D Q gives G_Sigma2D = -Q G_Q Q (the low-pass term is a
  // constant).
  Eigen::Matrix2f Q, G_Q;
  Q << g.conic.x(), g.conic.y(), g.conic.y(), g.conic.z();
  G_Q << upstream.conic.x(), 0.5f * upstream.conic.y(), 0.5f * upstream.conic.y(), upstream.conic.z();
  const Eigen::Matrix2f G_sigma_2d = -Q * G_Q * Q;

  // Forward intermediates, as in ProjectGaussian.
  const Eigen::Matrix3f R = model.rotations[index].normalized().toRotationMatrix();
  const Eigen::Vector3f s = model.log_scales[index].array().exp();
  const Eigen::Matrix3f M = R * s.asDiagonal();
  const Eigen::Matrix3f sigma = M * M.transpose();
  const float lim_x = 1.3f * camera.tan_half_fov_x, lim_y = 1.3f * camera.tan_half_fov_y;
  const bool clamped_x = std::abs(t.x() / t.z()) > lim_x, clamped_y = std::abs(t.y() / t.z()) > lim_y;
  const float tx = std::clamp(t.x() / t.z(), -lim_x, lim_x) * t.z();
  const float ty = std::clamp(t.y() / t.z(), -lim_y, lim_y) * t.z();
  const float tz = t.z(), tz2 = tz * tz, tz3 = tz2 * tz;
  Eigen::Matrix<float, 2, 3> J;
  J << camera.fx / tz, 0.0f, -camera.fx * tx / tz2,  //
      0.0f, camera.fy / tz, -camera.fy * ty / tz2;
  const Eigen::Matrix<float, 2, 3> T = J * W;

  // Sigma_2D = T Sigma T^T (T = J W), symmetric G and Sigma:
  //   dL/dSigma = T^T G T,  dL/dT = 2 G T Sigma,  dL/dJ = dL/dT W^T.
  const Eigen::Matrix3f G_sigma = T.transpose() * G_sigma_2d * T;
  const Eigen::Matrix<float, 2, 3> G_J = 2.0f * G_sigma_2d * T * sigma * W.transpose();

  // J(t): J00 = fx / tz, J11 = fy / tz, J02 = -fx tx' / tz^2 with tx' the clamped tx:
  //   unclamped (tx' = tx):      dJ02/dtx = -fx / tz^2,  dJ02/dtz = 2 fx tx / tz^3;
  //   clamped (tx' = r tz, r = +-lim, J02 = -fx r / tz): dJ02/dtx = 0, dJ02/dtz = fx r / tz^2 = fx tx' /
  //   tz^3.
  // Likewise J12 with fy, ty.
  Eigen::Vector3f dL_dt = Eigen::Vector3f::Zero();
  dL_dt.z() -= G_J(0, 0) * camera.fx / tz2 + G_J(1, 1) * camera.fy / tz2;
  if (clamped_x) {
    dL_dt.z() += G_J(0, 2) * camera.fx * tx / tz3;
  } else {
    dL_dt.x() -= G_J(0, 2) * camera.fx / tz2;
    dL_dt.z() += G_J(0, 2) * 2.0f * camera.fx * tx / tz3;
  }
  if (clamped_y) {
    dL_dt.z() += G_J(1, 2) * camera.fy * ty / tz3;
  } else {
    dL_dt.y() -= G_J(1, 2) * camera.fy / tz2;
    dL_dt.z() += G_J(1, 2) * 2.0f * camera.fy * ty / tz3;
  }

  // Mean (u, v) = (fx t_x / t_z + cx, fy t_y / t_z + cy) with the unclamped t:
  //   du/dt = (fx / tz, 0, -fx t_x / tz^2),  dv/dt = (0, fy / tz, -fy t_y / tz^2).  Depth t_z: dL/dt_z.
  const Eigen::Vector2f& g_uv = upstream.mean_2d;
  dL_dt.x() += g_uv.x() * camera.fx / tz;
  dL_dt.y() += g_uv.y() * camera.fy / tz;
  dL_dt.z() += -g_uv.x() * camera.fx * t.x() / tz2 - g_uv.y() * camera.fy * t.y() / tz2 + upstream.depth;
  gradients->mean_2d[index] += g_uv;

  // t = W mu + t_cw: dL/dmu = W^T dL/dt.
  dL_dmu += W.transpose() * dL_dt;
  gradients->position[index] += dL_dmu;

  // Sigma = M M^T, M = R S, S = diag(s), s = exp(log_scale):
  //   dL/dM = 2 G_Sigma M,  dL/ds_k = sum_j R_jk (dL/dM)_jk,  dL/dlog s_k = s_k dL/ds_k,
  //   dL/dR = dL/dM S.
  const Eigen::Matrix3f G_M = 2.0f * G_sigma * M;
  for (int k = 0; k < 3; ++k) gradients->log_scale[index][k] += s[k] * R.col(k).dot(G_M.col(k));
  const Eigen::Matrix3f G_R = G_M * s.asDiagonal();

  // R from q_hat = q / |q|: dL/dq = (dL/dq_hat - q_hat (q_hat . dL/dq_hat)) / |q|.
  const Eigen::Quaternionf& q = model.rotations[index];
  const Eigen::Quaternionf q_hat = q.normalized();
  const Eigen::Vector4f g_hat = RotationMatrixBackward(q_hat, G_R);
  const Eigen::Vector4f q_hat_wxyz(q_hat.w(), q_hat.x(), q_hat.y(), q_hat.z());
  gradients->rotation[index] += (g_hat - q_hat_wxyz * q_hat_wxyz.dot(g_hat)) / q.norm();
}

}  // namespace uf::splat
