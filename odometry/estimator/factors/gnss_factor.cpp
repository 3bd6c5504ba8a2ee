#include "odometry/estimator/factors/gnss_factor.h"

#include <Eigen/Cholesky>
#include <cassert>
#include <cmath>

#include "odometry/estimator/factors/interpolated_point.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

using Matrix36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
using Matrix34 = Eigen::Matrix<double, 3, kGnssAlignmentSize, Eigen::RowMajor>;

// r = L (rotated + t - f) with rotated = Rz(yaw) p_w; dr/d[yaw, t] = L [[e_z]x rotated, I] into J (3 x 4).
void AlignmentPart(const Eigen::Matrix3d& L, const Eigen::Vector3d& rotated, double* J) {
  if (J == nullptr) return;
  Eigen::Map<Matrix34> out(J);
  out.col(0) = L * Eigen::Vector3d(-rotated.y(), rotated.x(), 0.0);
  out.rightCols<3>() = L;
}

}  // namespace

Eigen::Vector3d EnuAlignment::Apply(const Eigen::Vector3d& p_world) const {
  return RotationZ(yaw_rad) * p_world + translation;
}

SE3 EnuAlignment::T_enu_world() const { return SE3(SO3(RotationZ(yaw_rad)), translation); }

Eigen::Matrix3d RotationZ(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix3d R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  return R;
}

std::array<double, kGnssAlignmentSize> AlignmentBlock(const EnuAlignment& alignment) {
  return {alignment.yaw_rad, alignment.translation.x(), alignment.translation.y(), alignment.translation.z()};
}

EnuAlignment AlignmentFromBlock(const double* block) {
  return EnuAlignment{block[0], Eigen::Vector3d(block[1], block[2], block[3])};
}

Eigen::Matrix3d GnssSqrtInformation(const Eigen::Matrix3d& covariance, GnssAxes axes) {
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  assert(llt.info() == Eigen::Success && "GNSS covariance must be positive definite");
  // L = C^-1 (C lower triangular): solve C L = I.
  Eigen::Matrix3d L = llt.matrixL().solve(Eigen::Matrix3d::Identity());
  if (axes == GnssAxes::kHorizontal) L.row(2).setZero();
  return L;
}

GnssFactor::GnssFactor(const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& covariance,
                       const Eigen::Vector3d& lever_arm, double alpha, GnssAxes axes)
    : fix_enu_(fix_enu),
      sqrt_information_(GnssSqrtInformation(covariance, axes)),
      lever_arm_(lever_arm),
      alpha_(alpha) {
  assert(alpha >= 0 && alpha <= 1);
}

bool GnssFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  if (jacobians == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  double J_a[18], J_b[18];
  double* tangent[3] = {jacobians[0] != nullptr ? J_a : nullptr, jacobians[1] != nullptr ? J_b : nullptr,
                        jacobians[2]};  // the alignment block is Euclidean: ambient = tangent
  EvaluateTangent(parameters, residuals, tangent);
  if (jacobians[0] != nullptr) TangentToAmbientJacobian(parameters[0], J_a, 3, jacobians[0]);
  if (jacobians[1] != nullptr) TangentToAmbientJacobian(parameters[1], J_b, 3, jacobians[1]);
  return true;
}

bool GnssFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const double* pose_a = parameters[0];
  const double* pose_b = parameters[1];
  const EnuAlignment alignment = AlignmentFromBlock(parameters[2]);
  PoseInterpolationTerms terms;
  ComputePoseInterpolationTerms(pose_a, pose_b, terms);
  const InterpolatedPoint antenna(terms, pose_a, pose_b, alpha_, lever_arm_);
  const Eigen::Matrix3d Rz = RotationZ(alignment.yaw_rad);
  const Eigen::Vector3d rotated = Rz * antenna.world();
  Eigen::Map<Eigen::Vector3d> r(residuals);
  r = sqrt_information_ * (rotated + alignment.translation - fix_enu_);
  if (jacobians == nullptr) return true;
  antenna.PullBack(sqrt_information_ * Rz, jacobians[0], jacobians[1]);  // dr/dp_w = L Rz
  AlignmentPart(sqrt_information_, rotated, jacobians[2]);
  return true;
}

GnssFactorSinglePose::GnssFactorSinglePose(const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& covariance,
                                           const Eigen::Vector3d& lever_arm, GnssAxes axes)
    : fix_enu_(fix_enu), sqrt_information_(GnssSqrtInformation(covariance, axes)), lever_arm_(lever_arm) {}

bool GnssFactorSinglePose::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  if (jacobians == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  double J_pose[18];
  double* tangent[2] = {jacobians[0] != nullptr ? J_pose : nullptr, jacobians[1]};
  EvaluateTangent(parameters, residuals, tangent);
  if (jacobians[0] != nullptr) TangentToAmbientJacobian(parameters[0], J_pose, 3, jacobians[0]);
  return true;
}

bool GnssFactorSinglePose::EvaluateTangent(double const* const* parameters, double* residuals,
                                           double** jacobians) const {
  const double* pose = parameters[0];
  const EnuAlignment alignment = AlignmentFromBlock(parameters[1]);
  const Eigen::Matrix3d R = RotationOfPoseBlock(pose);
  const Eigen::Vector3d p_w = R * lever_arm_ + Eigen::Map<const Eigen::Vector3d>(pose);
  const Eigen::Matrix3d Rz = RotationZ(alignment.yaw_rad);
  const Eigen::Vector3d rotated = Rz * p_w;
  Eigen::Map<Eigen::Vector3d> r(residuals);
  r = sqrt_information_ * (rotated + alignment.translation - fix_enu_);
  if (jacobians == nullptr) return true;
  if (jacobians[0] != nullptr) {
    const Eigen::Matrix3d L_Rz = sqrt_information_ * Rz;
    Eigen::Map<Matrix36> J(jacobians[0]);
    J << L_Rz, -L_Rz * R * Hat(lever_arm_);
  }
  AlignmentPart(sqrt_information_, rotated, jacobians[1]);
  return true;
}

}  // namespace uf::estimator
