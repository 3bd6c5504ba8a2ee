// The state of one keyframe in the sliding window and its layout as Ceres parameter blocks.
//
// State x_k = {R, t, v, b_a, b_g}: the pose T_world_imu = (R, t) of the IMU (body) frame, its velocity in the
// world, and the accelerometer and gyroscope biases (imu frame). In LO mode (no IMU) the body is the LiDAR
// frame and only the pose is estimated.
//
// Parameter blocks (what every factor's Evaluate receives):
//   pose[7]       = {t_x, t_y, t_z, q_x, q_y, q_z, q_w}   (Eigen's quaternion coefficient order)
//   speed_bias[9] = {v_x, v_y, v_z, ba_x, ba_y, ba_z, bg_x, bg_y, bg_z}
// The pose moves on PoseManifold: tangent delta = [dt; dtheta] (translation first, like uf::SE3 twists),
//   t <- t + dt,   R <- R Exp(dtheta)   (right-multiplicative, as the paper's update).
// Jacobians of residuals are taken with respect to that tangent (Ceres multiplies the ambient Jacobian by
// PlusJacobian; analytic factors may instead fill the ambient Jacobian so that this product gives the tangent
// one, see PoseManifold::PlusJacobian).
#pragma once

#include <Eigen/Core>
#include <array>

#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"

namespace uf::estimator {

constexpr int kPoseSize = 7;
constexpr int kPoseTangentSize = 6;
constexpr int kSpeedBiasSize = 9;

struct NavState {
  Stamp stamp = 0;
  SE3 T_world_imu;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();    // world frame, m/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // m/s^2, imu frame
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // rad/s, imu frame
};

// The state's parameter blocks and back.
std::array<double, kPoseSize> PoseBlock(const SE3& T);
SE3 PoseFromBlock(const double* pose);
std::array<double, kSpeedBiasSize> SpeedBiasBlock(const NavState& state);
void SetSpeedBias(const double* speed_bias, NavState& state);

}  // namespace uf::estimator
