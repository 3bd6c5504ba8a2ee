// A point fixed in the body frame, seen at fraction a in [0, 1] between two poses of the body, and its
// tangent Jacobians: the interpolation shared by the factors that observe the body between two nodes
// (PointToPlaneFactor: a LiDAR point during the sweep; GnssFactor: the antenna at the fix time).
//
// Blocks pose_b, pose_e = T_world_body (nav_state.h layout), tangents [dt; dtheta] (t <- t + dt,
// R <- R Exp(dtheta)). For a body point p_B:
//   d    = Log(R_b^T R_e)
//   R(a) = R_b Exp(a d),   t(a) = (1 - a) t_b + a t_e                    (slerp / lerp)
//   p_w  = R(a) p_B + t(a)
// Jacobians (Jr, Jl: right/left Jacobians of SO3, u = a d):
//   dp_w/dt_b = (1 - a) I,   dp_w/dt_e = a I
//   R(a) moves as R(a) Exp(Phi dtheta) with
//     Phi_b = Exp(u)^T - a Jr(u) Jl(d)^-1     (from Log(Exp(-db) Exp(d)) ~ d - Jl(d)^-1 db)
//     Phi_e = a Jr(u) Jr(d)^-1                (from Log(Exp(d) Exp(de)) ~ d + Jr(d)^-1 de)
//   and p_w moves by -R(a) [p_B]x Phi dtheta, so dp_w/dtheta_{b,e} = -R(a) [p_B]x Phi_{b,e}.
// a = 0 gives Phi_b = I, Phi_e = 0; a = 1 gives Phi_b = 0, Phi_e = I; R_b = R_e gives (1 - a) I and a I.
//
// A factor with residual r(p_w) needs dr/dp_w * dp_w/d(blocks). PullBack forms it row vector first
// (G R(a) [p_B]x, then the products with Phi), which costs far less than the 3 x 12 Jacobian for a
// one-row residual. Everything here is inline and allocation-free: it is the LiDAR factor's hot path. Exp(u)
// and Jr(u) share their coefficients and K = [u]x (so3.cpp's closed forms, evaluated once):
//   Exp(u) = I + A K + B K^2,   Jr(u) = I - B K + C K^2,
//   A = sin / theta,  B = (1 - cos) / theta^2,  C = (theta - sin) / theta^3,  theta = |u|.
#pragma once

#include <Eigen/Core>

#include "odometry/types/lie_coefficients.h"
#include "odometry/types/so3.h"

namespace uf::estimator {

// What every point between one pair of pose blocks shares.
struct PoseInterpolationTerms {
  Eigen::Matrix3d R_b, R_e;            // the blocks' rotations (quaternions normalised)
  Eigen::Vector3d d;                   // Log(R_b^T R_e)
  Eigen::Matrix3d Jl_inv_d, Jr_inv_d;  // Jl(d)^-1, Jr(d)^-1
};

// The rotation of a pose block (its quaternion normalised).
Eigen::Matrix3d RotationOfPoseBlock(const double* pose);

// Fills `terms` for the pose blocks pose_b, pose_e (7 doubles each).
void ComputePoseInterpolationTerms(const double* pose_b, const double* pose_e, PoseInterpolationTerms& terms);

class InterpolatedPoint {
 public:
  // `terms` (of the same pose_b, pose_e) must outlive this object; alpha in [0, 1]. The constructor and
  // PullBack are forced inline: GCC otherwise keeps them out of line, and the LiDAR factor pays the calls
  // and the round trip through memory on every point.
  EIGEN_ALWAYS_INLINE InterpolatedPoint(const PoseInterpolationTerms& terms, const double* pose_b,
                                        const double* pose_e, double alpha, const Eigen::Vector3d& point_body)
      : terms_(terms),
        alpha_(alpha),
        point_body_(point_body),
        u_(alpha * terms.d),
        theta_(u_.norm()),
        K_(Hat(u_)),
        K2_(K_ * K_),
        B_(lie::OneMinusCosOverTheta2(theta_)),
        Exp_u_(Eigen::Matrix3d::Identity() + lie::SinOverTheta(theta_) * K_ + B_ * K2_),
        R_a_(terms.R_b * Exp_u_) {
    const Eigen::Map<const Eigen::Vector3d> t_b(pose_b), t_e(pose_e);
    t_a_ = (1.0 - alpha) * t_b + alpha * t_e;
    p_w_ = R_a_ * point_body_ + t_a_;
  }

  const Eigen::Vector3d& world() const { return p_w_; }        // p_w
  const Eigen::Matrix3d& rotation() const { return R_a_; }     // R(a)
  const Eigen::Vector3d& translation() const { return t_a_; }  // t(a)

  // The chain rule through the interpolation: for G = dr/dp_w (Rows x 3), writes dr/d[dt_b; dtheta_b] to
  // J_b and dr/d[dt_e; dtheta_e] to J_e (each Rows x 6, row-major; a null pointer skips that block).
  template <typename Derived>
  EIGEN_ALWAYS_INLINE void PullBack(const Eigen::MatrixBase<Derived>& dr_dp, double* J_b, double* J_e) const {
    constexpr int Rows = Derived::RowsAtCompileTime;
    static_assert(Derived::ColsAtCompileTime == 3, "dr/dp_w has 3 columns");
    using RowsBy3 = Eigen::Matrix<double, Rows, 3, Rows == 1 ? Eigen::RowMajor : Eigen::ColMajor>;
    using RowsBy6 = Eigen::Matrix<double, Rows, 6, Eigen::RowMajor>;
    if (J_b == nullptr && J_e == nullptr) return;
    const RowsBy3 G = dr_dp;
    // dr/dphi for R(a) <- R(a) Exp(phi): w = -G R(a) [p_B]x; then w Phi_{b,e} (w Jr(u) is shared).
    const RowsBy3 w = -(G * R_a_) * Hat(point_body_);
    const Eigen::Matrix3d Jr_u =
        Eigen::Matrix3d::Identity() - B_ * K_ + lie::ThetaMinusSinOverTheta3(theta_) * K2_;
    const RowsBy3 w_Jr_u = w * Jr_u;
    if (J_b != nullptr) {
      Eigen::Map<RowsBy6> J(J_b);
      J << (1.0 - alpha_) * G, w * Exp_u_.transpose() - alpha_ * w_Jr_u * terms_.Jl_inv_d;
    }
    if (J_e != nullptr) {
      Eigen::Map<RowsBy6> J(J_e);
      J << alpha_ * G, alpha_ * w_Jr_u * terms_.Jr_inv_d;
    }
  }

  // dp_w/d[dt_b, dtheta_b, dt_e, dtheta_e] (3 x 12).
  Eigen::Matrix<double, 3, 12> Jacobian() const {
    Eigen::Matrix<double, 3, 6, Eigen::RowMajor> J_b, J_e;
    PullBack(Eigen::Matrix3d::Identity(), J_b.data(), J_e.data());
    Eigen::Matrix<double, 3, 12> J;
    J << J_b, J_e;
    return J;
  }

 private:
  const PoseInterpolationTerms& terms_;
  const double alpha_;
  const Eigen::Vector3d point_body_;  // p_B
  const Eigen::Vector3d u_;           // a d
  const double theta_;                // |u|
  const Eigen::Matrix3d K_, K2_;      // [u]x and its square
  const double B_;                    // (1 - cos(theta)) / theta^2
  const Eigen::Matrix3d Exp_u_;       // Exp(a d)
  const Eigen::Matrix3d R_a_;         // R(a)
  Eigen::Vector3d t_a_, p_w_;
};

}  // namespace uf::estimator
