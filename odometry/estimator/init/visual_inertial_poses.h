// The visual-inertial initialization's poses (docs/METHOD.md "Visual-inertial odometry", mode D; the paper's
// short-window structure from motion with inertial alignment, as VINS-Mono's with the gyro's rotations):
// metric poses of the IMU at the nodes of the initialization window, in the frame "lo" of the first node's
// IMU, from the camera's feature tracks and the IMU alone, while the body moves.
//
// The gyro gives the rotations R_k (R_0 = I) and, with the accelerometer, a_k, the position node k would
// have from rest without gravity, and b_k, the velocity it would have gained (preintegration chained from
// node 0); t_k is node k's time since node 0.
// 1. Up-to-scale structure from motion, with the rotations known (rays r in "lo"), from the tracks seen at
//    both ends of the window whose end rays part by min_parallax: the baseline c_last (|c_last| = 1) is
//    the direction every such track's two end rays share a plane with, (r_0 x r_last)^T c_last = 0
//    (smallest singular vector; its sign the one that puts most points in front); the points are
//    triangulated from their end rays; then, three times in turn, each node's centre is the one whose rays
//    miss the points least, sum |(I - r r^T)(P - c_k)|^2 / |P - c_k|^2 (a resection with the rotation
//    known: linear), and each point is triangulated again from all its rays, likewise weighted. A
//    forward-driving camera's two-view constraints alone would leave the ratios of collinear baselines free;
//    the points fix them.
// 2. The structure and the gyro bias together by a bundle adjustment (init/gyro_bias_bundle.h), the
//    preintegrations then chained again at that bias (init/imu_chain.h): the rotations R_k, a_k and b_k
//    below are the corrected ones.
// 3. Inertial alignment: the IMU's position is p_k = s c_k - R_k t_bc + t_bc (p_0 = 0, T_body_camera =
//    (R_bc, t_bc)) and also v_0 t_k + g t_k^2 / 2 + a_k, linear in [s, v_0, g] (scale, first velocity,
//    gravity in "lo"); least squares, with their covariance from the fit's residual.
//    With a stereo rig (FeatureTrack::depths) the scale is the rig's instead: each spanning track's depth
//    from the rig at a node over its depth in the up-to-scale structure there, the median over at least 5
//    tracks (fewer: the accelerometer's scale, as without a rig); the fit is then linear in [v_0, g].
// The start is taken only when
// - the scale is the rig's, or the specific force is not constant over the window: the velocity it adds
//   departs by at least min_velocity_excursion_mps from the straight line in time that a constant one adds.
//   At a steady velocity the accelerometer sees nothing of the motion, and a constant acceleration is taken
//   up by g (a free vector here): the scale is not observed (Wu, Guo, Roumeliotis, "VINS on wheels", ICRA
//   2017). The rig's scale needs no excitation: with s known, v_0 t_k and g t_k^2 / 2 part by their time;
// - s > 0, |g| is within max_gravity_error of gravity, gravity's direction is pinned within max_tilt_sigma
//   and v_0 within max_velocity_sigma.
//
// Assumed: the accelerometer bias is zero over the window (it tilts the gravity found by b_a / g); the
// window then estimates it.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "odometry/estimator/init/gyro_bias_bundle.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

// One feature's observations: node index in the window and undistorted normalized coordinates there; with a
// stereo rig, its depth (z in the camera, m) from the rig's pair at some of those nodes.
struct FeatureTrack {
  TrackObservations observations;
  std::vector<std::pair<std::size_t, double>> depths;
};

struct VisualInertialStartConfig {
  double gravity = 9.80665;                                   // m/s^2
  double max_gravity_error = 0.1;                             // |g| within this fraction of gravity
  double max_tilt_sigma_rad = 0.25 * 3.14159265358979 / 180;  // gravity direction's standard deviation
  double max_velocity_sigma_mps = 0.1;                        // v_0's, its largest axis
  double min_velocity_excursion_mps = 0.1;  // over the window (1 s: a change of acceleration of ~0.4 m/s^2)
  int min_tracks = 20;                      // features seen from 3 nodes at least
  double min_parallax_rad = 1.0 * 3.14159265358979 / 180;  // between a track's end rays
};

struct VisualInertialStart {
  std::vector<SE3> poses;                                                                 // T_lo_imu per node
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero(), gravity = Eigen::Vector3d::Zero();  // v_0, g in "lo"
  double tilt_sigma_rad = 0, velocity_sigma_mps = 0;
  int tracks = 0;  // used
  double scale = 0;             // s of the alignment, the camera centres' units in metres
  bool scale_from_rig = false;  // s is the stereo rig's (not the accelerometer's)
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  // rad/s, from the bundle adjustment
  double reprojection_rms = 0;                          // the structure's after it, normalized image units
};

// preintegrations[k] between nodes k and k + 1 (linearized at zero biases); tracks over those nodes.
// Fails, with the reason, when too few tracks are usable or the start is not pinned (see above).
Expected<VisualInertialStart> VisualInertialPoses(std::span<const ImuPreintegration> preintegrations,
                                                  const std::vector<FeatureTrack>& tracks,
                                                  const SE3& T_body_camera,
                                                  const VisualInertialStartConfig& config);

}  // namespace uf::estimator
