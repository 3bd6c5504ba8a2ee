#include "odometry/estimator/factors/interpolated_point.h"

#include <Eigen/Geometry>

namespace uf::estimator {

Eigen::Matrix3d RotationOfPoseBlock(const double* pose) {
  return Eigen::Map<const Eigen::Quaterniond>(pose + 3).normalized().toRotationMatrix();
}

void ComputePoseInterpolationTerms(const double* pose_b, const double* pose_e,
                                   PoseInterpolationTerms& terms) {
  terms.R_b = RotationOfPoseBlock(pose_b);
  terms.R_e = RotationOfPoseBlock(pose_e);
  terms.d = SO3(terms.R_b.transpose() * terms.R_e).Log();
  terms.Jl_inv_d = LeftJacobianInverseSO3(terms.d);
  terms.Jr_inv_d = RightJacobianInverseSO3(terms.d);
}

}  // namespace uf::estimator
