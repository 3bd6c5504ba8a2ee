// Configuration of the wheel-inertial odometry window (WIO, inertial_odometry/inertial_odometry.h): nodes
// on a fixed grid of IMU time linked by IMU preintegration and wheel odometry factors. Plain struct with
// documented defaults and a Validate that names the first bad field ("wio.<field>: must be ..., got
// <value>"; the nested parts "wio.imu.", "wio.init.", "wio.wheel.", "wio.marginalization.").
#pragma once

#include <memory>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/config/imu_noise_params.h"
#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/config/marginalization_config.h"
#include "odometry/estimator/config/visual_factor_config.h"
#include "odometry/estimator/config/wheel_factor_config.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct InertialOdometryConfig {
  // A node every node_interval_s of IMU time. 0.1 s: the wheel's 10-50 Hz gives every interval a few
  // samples, and the preintegration's first-order bias update stays accurate (VINS-Mono's keyframes are
  // 0.05-0.2 s apart).
  double node_interval_s = 0.1;  // s
  int window_size = 20;          // nodes in the window (2 s at 0.1 s), >= init_window_nodes
  // The inertial initialization waits for this many nodes (1 s at 0.1 s): the static alignment needs the
  // IMU at rest over them, the wheel-aided one enough motion to separate gravity from acceleration.
  int init_window_nodes = 10;
  // Dense Levenberg-Marquardt iterations per solve (one solve per node), and its wall-time budget. With the
  // camera the window uses visual.max_iterations and visual.max_solver_time_s instead.
  int max_iterations = 5;
  double max_solver_time_s = 0.05;  // per solve, s
  bool marginalize = true;          // oldest nodes into a Gaussian prior (else dropped with their factors)
  MarginalizationConfig marginalization;

  // The IMU's white-noise densities: twice the ADIS16448 datasheet values the simulator uses, for the
  // discretisation of the preintegration (midpoint rule, boundary interpolation). Unlike LIO there are no
  // hundreds of point-to-plane residuals to balance, so the datasheet scale is kept.
  ImuNoiseParams imu = {.accel_noise_density = 4.0e-3, .gyro_noise_density = 3.4e-4};
  InertialInitConfig init;  // its static and gravity-norm keys (the LIO-only ones are not used)
  // The biases' prior at initialization (factors/bias_prior_factor.h), about the alignment's estimate: the
  // only bound on the tilt / accelerometer-bias pair while the vehicle drives straight. 0.02 m/s^2 (2 mg)
  // is the turn-on bias of a factory-calibrated MEMS accelerometer; 0.002 rad/s (0.1 deg/s) covers the
  // alignment's gyro bias (the mean rate at rest, or the rotations of the moving start).
  double init_accel_bias_sigma = 0.02;  // m/s^2
  double init_gyro_bias_sigma = 0.002;  // rad/s
  double imu_max_gap_s = 0.05;  // a longer step between IMU samples is a gap: the window restarts after it
  double max_speed_mps = 80;    // a faster state is divergence: logged re-initialization

  // Wheel odometry factors (WIO, VWIO); false: none (VIO), and the nodes wait for the IMU alone.
  bool use_wheel = true;
  WheelFactorConfig wheel;
  SE3 T_body_wheel;  // the wheel (base) frame in the body (IMU) frame, from the calibration
  // A node the IMU covers waits this long (IMU time) for the wheel to cover it too; then it is added with
  // the IMU factor alone (the wheel stream stalled; a warning).
  double wheel_max_wait_s = 0.5;  // s

  // GNSS position factors (WGIO; providers/gnss_provider.h): the 4-dof ENU alignment starts once the
  // antenna has moved; fixes never hold nodes back.
  bool use_gnss = false;
  GnssFactorConfig gnss;
  SE3 T_body_gnss;  // the antenna in the body (IMU) frame; its translation is the lever arm

  // Camera factors (VIO, VWIO; providers/visual_provider.h): a node at every frame (its stamp + t_d)
  // instead of the grid, and reprojection factors between them. Needs the tracked camera's model and its
  // pose in the body (IMU) frame. Without the wheel the start is static or visual-inertial (mode D).
  bool use_camera = false;
  VisualFactorConfig visual;
  std::shared_ptr<const CameraModel> camera;
  SE3 T_body_camera;
  // A stereo rig's second camera and its pose in the body frame (used with visual.stereo); none: monocular.
  std::shared_ptr<const CameraModel> right_camera;
  SE3 T_body_right_camera;

  Status Validate() const;
};

}  // namespace uf::estimator
