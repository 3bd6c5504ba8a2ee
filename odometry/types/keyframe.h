// What the estimator hands to mapping for each keyframe: the optimised state, the deskewed scan already in
// the world frame, the images taken near the keyframe time, and how reliable each sensor was.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"

namespace uf {

// How well the scan's point-to-plane factors pin its pose (docs/METHOD.md "Factor-wise reliability
// scheduling", LiDAR score): from their Gauss-Newton information H (6x6, tangent [dt (world); dtheta
// (body)]) at registration.
struct LidarDegeneracy {
  int matches = 0;                  // point-to-plane residuals
  double translation_isotropy = 0;  // lambda_min / mean eigenvalue of H's translation block, in [0, 1]
  double rotation_isotropy = 0;     // the same of its rotation block
  Eigen::Vector3d weak_translation = Eigen::Vector3d::Zero();  // world, unit: least constrained direction
  double score = 1.0;  // D in [0, 1]: 0 pins every direction, 1 leaves one free
};

// How well the wheel's motion over the node interval ending at the keyframe agreed with the IMU's prediction
// of it (docs/METHOD.md "Factor-wise reliability scheduling", wheel score), and whether its factor joined the
// window.
struct WheelConsistency {
  double speed_error_mps = 0;       // |u - u_0|: u = (dp_wheel - dp_imu) / dt in the wheel's plane, u_0
                                    // its recent level (schedule/wheel_consistency.h)
  double speed_change_error_mps = 0;  // c: the wheel's speed change against the IMU's, over a short window
  double yaw_rate_error_rad_s = 0;  // |dpsi_wheel - dpsi_imu| / dt, about the wheel's vertical
  double score = 0;                 // D in [0, 1]: 0 agrees, 1 contradicts
  bool active = true;               // the interval's wheel factor joined the window
};

// How reliable the IMU was over the node interval ending at the keyframe (docs/METHOD.md "Factor-wise
// reliability scheduling", IMU score; schedule/imu_score.h), at the window's last estimate of it.
struct ImuReliability {
  double excitation = 0;           // eta in [0, 1]: the interval's rotation rate or acceleration, full at
                                   // 0.1 rad/s or 0.5 m/s^2
  double preintegration_chi2 = 0;  // the IMU factor's squared Mahalanobis residual (15 dof)
  int clipped_steps = 0;           // integration steps with a reading at the sensor's full scale
  double score = 0;                // D in [0, 1]: 0 reliable, 1 not
};

// A GNSS fix as the reliability scheduling sees it (docs/METHOD.md "Factor-wise reliability scheduling",
// GNSS score; schedule/gnss_score.h), and whether the innovation test let its factor in.
struct GnssCheck {
  Stamp stamp = 0;                 // the fix's
  double fix_quality = 0;          // q_fix in [0, 1] from its status
  double covariance_trace_m2 = 0;  // tr(Sigma) of the fix
  double innovation_d2 = 0;        // squared Mahalanobis innovation against the window's prediction (3 dof)
  double score = 0;                // D in [0, 1]
  bool active = true;              // its factor joined the window (with all axes or horizontally)
};

// A camera frame as the reliability scheduling sees it (docs/METHOD.md "Factor-wise reliability scheduling",
// camera scheduling; schedule/camera_motion_check.h): its tracks held against the window's predicted motion,
// and whether its observations joined the window.
struct CameraCheck {
  Stamp stamp = 0;             // the frame's node
  int tracks_checked = 0;      // tracks seen at an earlier node of the window
  int tracks_agreeing = 0;     // of those, explained by the predicted motion within the tolerance
  double grid_occupancy = 0;   // share of the 8x8 grid cells holding an agreeing track
  double motion_error_px = 0;  // the checked tracks' median disagreement with the prediction, px
  double score = 0;            // D in [0, 1]
  bool active = true;          // its observations joined the window
};

struct Keyframe {
  Stamp stamp = 0;
  SE3 T_world_body;                                     // body (IMU in LIO, LiDAR in LO) to world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();   // of the body, in the world frame, m/s
  Eigen::Vector3d bias_acc = Eigen::Vector3d::Zero();   // accelerometer bias, imu frame, m/s^2
  Eigen::Vector3d bias_gyro = Eigen::Vector3d::Zero();  // gyroscope bias, imu frame, rad/s
  bool inertial = false;  // velocity and biases are an inertial window's estimates (else not estimated)
  // The LiDAR extrinsic's translation (T_body_lidar's, m) as the window estimated it when the keyframe left
  // (lio.estimate_lidar_translation; its body pose is moved to the settled estimate, docs/METHOD.md "Online
  // spatiotemporal calibration"); none where the translation is held as given.
  std::optional<Eigen::Vector3d> lidar_translation;
  std::vector<Eigen::Vector3f> scan_world;              // deskewed scan, world frame, m
  std::vector<float> scan_intensity;  // one per point of scan_world, as the sensor reports it
  std::vector<CameraFrame> images;    // frames taken near stamp, any cameras of the rig
  std::optional<LidarDegeneracy> lidar_degeneracy;  // LiDAR window: of its registration (none if rejected)
  std::optional<ImuReliability> imu_reliability;    // with an IMU: of the node interval ending here
  std::optional<WheelConsistency> wheel_consistency;  // with wheel scheduling: of the interval ending here
  std::vector<GnssCheck> gnss_checks;  // the fixes the innovation test saw since the previous keyframe
  std::vector<CameraCheck> camera_checks;  // with the camera: its frames checked since the previous keyframe
};

}  // namespace uf
