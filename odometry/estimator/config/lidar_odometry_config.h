// Configuration of the LiDAR odometry window, LiDAR-only (LO) or LiDAR-inertial (LIO, use_imu): plain struct
// with the paper's defaults and a Validate that names the first bad field ("lo.<field>: must be ..., got
// <value>"; the LIO fields are "lio.<field>").
#pragma once

#include <memory>

#include "odometry/estimator/config/constant_velocity_noise.h"
#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/config/imu_noise_params.h"
#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/config/marginalization_config.h"
#include "odometry/estimator/config/visual_factor_config.h"
#include "odometry/estimator/config/voxel_map_config.h"
#include "odometry/estimator/config/wheel_factor_config.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct LidarOdometryConfig {
  double input_voxel_m = 1.0;         // downsampling of each scan for registration, m
  VoxelMapConfig map;                 // voxel 0.5 m, eigen-ratio 0.12 (paper)
  int window_size = 10;               // scans (states) in the window, >= 2 (real-time profile 4)
  int max_iterations = 8;             // LM iterations per solve (paper 8 / 40 ms)
  double max_solver_time_s = 0.04;    // per solve, s
  // The window's solve takes each scan's point-to-plane factors as their Gauss-Newton model, kept while the
  // scan's poses stay near its linearization point; where they moved past it after a solve, the models are
  // condensed again and the window solved again, at most this many solves in all (window/condensed_factor.h,
  // docs/METHOD.md "Sliding window and solve"); 0: the residuals themselves at every iteration, as in a
  // window holding a scan taken through a reliability projector.
  int condensed_lidar_rounds = 2;
  int max_residuals_per_scan = 1500;  // point-to-plane residuals of one scan (paper 1200-2000)
  double huber_m = 0.1;               // robust loss scale, m of point-to-plane distance (paper 0.5-1.0)
  double min_range_m = 1.0, max_range_m = 100.0;  // points kept for registration and the map, m
  SE3 T_body_lidar;                               // identity in LO mode (body = lidar); T_imu_lidar in LIO
  // Beyond the list (defaults tuned on KITTI 00 keyframes and the simulator):
  double map_insert_voxel_m = 0.5;    // downsampling of the deskewed scan inserted into the map, m
  int association_rounds = 10;        // at most this many solve + re-query rounds per scan (ICP style)
  double max_plane_distance_m = 1.0;  // correspondences farther from their plane are dropped, m
  ConstantVelocityNoise motion;       // constant-velocity prior between consecutive pose nodes
  // Registration acceptance and recovery (docs/METHOD.md "Registration, acceptance and recovery"):
  double min_match_ratio = 0.6;        // a registration whose fraction of points on a map plane is below this
                                       //   share of the recent scans' (their median) is rejected
  double max_speed_mps = 80;           // a scan registered farther from the last registered one than this
                                       //   speed allows is rejected; in LIO also a faster state is divergence
  double max_angular_rate_rad_s = 10;  // likewise for its rotation (10 rad/s = 573 deg/s)
  int max_rejected_scans = 3;          // this many consecutive rejections restart the local map
  double max_prediction_s = 0.5;       // the constant-velocity guess extrapolates at most this far
  int min_points = 50;                 // scans with fewer prepared points are skipped
  bool marginalize = true;             // oldest states into a Gaussian prior (else: oldest pose held fixed)
  // Reliability scheduling of the LiDAR (docs/METHOD.md "Factor-wise reliability scheduling"): a registered
  // scan's point-to-plane factors lose their say along its weak directions (WeakDirectionProjector); the
  // IMU, wheel or motion prior carry those.
  bool drop_weak_directions = false;
  MarginalizationConfig marginalization;

  // LIO: IMU preintegration factors between the states instead of the constant-velocity prior.
  bool use_imu = false;
  // The IMU's white-noise densities, 10x the ADIS16448 datasheet values the simulator uses: the margin
  // covers the discretisation of preintegration, the interpolation at scan boundaries and solves cut short
  // by the iteration budget. With the datasheet values the IMU factors are ~1e6 times stiffer than the
  // point-to-plane ones and the budgeted solves drift (simulated urban 20 s: ATE 0.11 m; 3x-30x: 0.006 m).
  ImuNoiseParams imu = {.accel_noise_density = 2.0e-2, .gyro_noise_density = 1.7e-3};
  InertialInitConfig init;
  double imu_max_gap_s = 0.05;  // a longer step between IMU samples is a gap: bridged with the
                                //   constant-velocity prior and a warning
  double imu_max_wait_s = 0.5;  // a scan waits this long (stream time) for the IMU to cover its end
  // Initialized LIO: each new sweep's points are first corrected by the IMU's motion within the sweep, its
  // departure from the constant velocity between the sweep's begin and end nodes (ImuSweepCorrection in
  // lidar_odometry/imu_sweep_correction.h); the window then interpolates between the nodes as before. Off
  // by default: it tips the 16-beam corridor's LWIO, already stuck far behind the truth, into shutting its
  // wheel gate (docs/METHOD.md "LiDAR point-to-plane factor").
  bool imu_deskew = false;
  // Initialized LIO: the translation t_BL of T_body_lidar estimated in the window (docs/METHOD.md "Online
  // spatiotemporal calibration"; needs imu_deskew): every point-to-plane factor takes it from one shared
  // block (PointToPlaneLeverFactor), under a prior of lidar_translation_sigma_m about the given one. The
  // block moves in a window solve only while the window's orientations spread by at least
  // lidar_translation_min_turn_deg about every axis (LeverExcited): turning about one axis leaves the
  // lever arm along it unseen. Keyframes that leave the window before it settles wait for it (at most 50).
  bool estimate_lidar_translation = false;
  double lidar_translation_sigma_m = 0.05;
  double lidar_translation_min_turn_deg = 1.0;

  // Wheel odometry factors between consecutive nodes (LWIO; providers/wheel_provider.h). A scan then also
  // waits (at most imu_max_wait_s of stream time) for the wheel samples to cover its end.
  bool use_wheel = false;
  // LWIO keeps the constant soft non-holonomic noise it was measured with (0.2 m/s/sqrt(Hz), no tilt terms)
  // rather than WIO's speed-dependent model (wheel_factor_config.h): with that model the LiDAR-degenerate
  // corridor start lags further (simulated corridor 60 s: ATE 0.109 -> 0.231 m; the estimate falls behind
  // while the vehicle pulls away either way, 0.5 m and 1.3 m at 5 s; docs/METHOD.md "Wheel factor"), which
  // needs its own look. The stationary branch is on (wheel_factor_config.h): at rest the LiDAR's
  // registration wanders along a corridor, and the window took that for motion.
  WheelFactorConfig wheel = {.nonholonomic_velocity_density = 0.2,
                             .suspension_tilt_sigma = 0.0,
                             .tilt_per_acceleration = 0.0,
                             .stationary_updates = true,
                             .schedule = {}};
  SE3 T_body_wheel;  // the wheel (base) frame in the body frame, from the calibration like T_body_lidar
  // Reliability scheduling of the LiDAR beside the wheel (docs/METHOD.md "Factor-wise reliability
  // scheduling"): where a registered scan pins a translation weakly (below 0.1 of its mean) and less than the
  // wheel does over its interval (forward speed and non-holonomic terms; also while the wheel's gate is
  // shut), its point-to-plane factors lose their say along it (LooseTranslationProjector): along a corridor's
  // axis the planes fitted to the scan lines held the estimate back while the vehicle pulled away.
  // drop_weak_directions, when on, drops more.
  bool wheel_carries_weak_translations = true;

  // GNSS position factors (LIO+G, LWGIO; providers/gnss_provider.h). Needs use_imu: the factor's 4-dof
  // alignment (yaw and translation) holds only in a gravity-aligned world.
  bool use_gnss = false;
  GnssFactorConfig gnss;
  SE3 T_body_gnss;  // the antenna in the body frame (its translation is the lever arm)

  // Camera factors (LVIO, LVWIO, LVWGIO; providers/visual_provider.h): each frame joins the scan node
  // nearest its stamp + t_d, and its features get their depth from the LiDAR map (else by triangulation).
  // Needs use_imu, the tracked camera's model and its pose in the body (IMU) frame. The window then solves
  // with visual.max_iterations and visual.max_solver_time_s.
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
