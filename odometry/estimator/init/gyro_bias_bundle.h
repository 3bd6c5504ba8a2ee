// The visual-inertial start's bundle adjustment (docs/METHOD.md "Visual-inertial odometry", mode D, step 2):
// the up-to-scale structure from motion refined together with the gyro bias. The camera's orientation at
// node k is the gyro's, R_k(b_g) R_bc (init/imu_chain.h), so the bias is three unknowns shared by every node
// instead of a rotation per node; with the centres c_1 .. c_last (c_0 = 0, |c_last| = 1 fixes the scale)
// and the points P, the cost is the reprojections' in normalized image coordinates,
//   sum rho(| pi((R_k(b_g) R_bc)^T (P - c_k)) - x |^2),  pi(q) = (q_x / q_z, q_y / q_z),
// rho Huber's. Levenberg-Marquardt with the points eliminated (Schur complement on their 3 x 3 blocks).
// The gyro's rotations drift by the bias over the window (0.005 rad/s: 0.3 deg in 1 s), which bends the
// rays of the linear structure; here the rays decide how much of the rotation was the bias.
#pragma once

#include <Eigen/Core>
#include <span>
#include <utility>
#include <vector>

#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

// One feature's observations: node index in the window and undistorted normalized coordinates there.
using TrackObservations = std::vector<std::pair<std::size_t, Eigen::Vector2d>>;

struct GyroBiasBundle {
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  // rad/s
  std::vector<Eigen::Vector3d> centres, points;         // in the units of |c_last| = 1
  double reprojection_rms = 0;                          // at the result, normalized image units
};

// preintegrations[k] between nodes k and k + 1 (linearized at zero biases); tracks[f] observes points[f];
// centres and points from the linear structure at a zero bias.
GyroBiasBundle AdjustWithGyroBias(std::span<const ImuPreintegration> preintegrations,
                                  std::span<const TrackObservations> tracks, const SE3& T_body_camera,
                                  std::vector<Eigen::Vector3d> centres, std::vector<Eigen::Vector3d> points);

}  // namespace uf::estimator
