// Stereo factor at a landmark's anchor (docs/METHOD.md "Stereo in the window"): the rig's second camera sees
// the feature at the same instant as the anchor camera, so the pair constrains the landmark's inverse depth
// alone; the observations at other keyframes use ReprojectionFactor (with its T_target_camera for the second
// camera).
//
// Blocks: lambda (1, inverse depth in the anchor camera, 1/m), t_d (1, camera time offset, s). With the
// anchor's normalized coordinates u and the second camera's u_r, both moved to the node's time along the
// anchor feature's image velocity v (the rig's cameras are synchronous, reprojection_factor.h):
//   u'   = u - (t_d - t_d0) v,   u_r' = u_r - (t_d - t_d0) v
//   P_c  = (u', 1) / lambda,     P_r = R_rc P_c + t_rc     (T_rc: the anchor camera in the second's frame)
//   r    = s (pi(P_r) - u_r')
// Jacobians, with D = dpi/dP at P_r:
//   dr/dlambda = -s D R_rc P_c / lambda,   dr/dt_d = -s D R_rc (v, 0) / lambda + s v
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "odometry/estimator/factors/reprojection_factor.h"
#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

class StereoAnchorFactor : public ceres::SizedCostFunction<2, 1, 1>, public TangentJacobianCost {
 public:
  // anchor: the anchor camera's observation (its velocity moves both); right_normalized: the second
  // camera's undistorted normalized coordinates; td0: the offset the anchor's node was made with;
  // sqrt_information: s = the second camera's focal length / pixel sigma (> 0, asserted).
  StereoAnchorFactor(const FeatureObservation& anchor, const Eigen::Vector2d& right_normalized, double td0,
                     double sqrt_information, const SE3& T_right_camera);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // Both blocks are Euclidean: the tangent Jacobians are the ambient ones.
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override {
    return Evaluate(parameters, residuals, tangent_jacobians);
  }

 private:
  const FeatureObservation anchor_;
  const Eigen::Vector2d right_;
  const double td0_;
  const double sqrt_information_;
  const Eigen::Matrix3d R_rc_;
  const Eigen::Vector3d t_rc_;
};

}  // namespace uf::estimator
