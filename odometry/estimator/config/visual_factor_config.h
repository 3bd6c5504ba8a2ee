// Options of the visual factors in a window (providers/visual_provider.h; docs/METHOD.md "Visual
// reprojection factor" and "Visual-inertial odometry"): the front end, the noise and robust loss of a
// reprojection, when a feature becomes a landmark, when it is dropped as an outlier, and the camera time
// offset t_d. Validate names the first bad field ("visual.<field>: must be ..., got <value>"; the window
// prefixes "wio." or "lio.").
#pragma once

#include "odometry/estimator/config/feature_tracker_config.h"
#include "odometry/types/status.h"

namespace uf::estimator {

// Reliability scheduling of the camera (docs/METHOD.md "Factor-wise reliability scheduling", camera
// scheduling; schedule/camera_motion_check.h, schedule/activation_gate.h): each frame's tracks are held
// against the window's predicted motion before its observations join the window and the frame is scored
// (always); with `enabled` a frame is left out while the gate is shut. Off by default: on the simulated
// faults it does not pay (a textured panel crossing the view: VIO and VWIO ATE +4 % on the mean of 3 seeds;
// darkness: -7 %). The landmarks' own outlier checks already keep the panel's tracks out, and leaving its
// frames out loses the scene's tracks in them too (docs/METHOD.md "Factor-wise reliability scheduling").
struct VisualScheduleConfig {
  bool enabled = false;
  // A track agrees with the predicted motion within this. The prediction of a new node (the IMU's over one
  // frame interval, or the LiDAR's) is off by about a centimetre, a few pixels on the road 3 m ahead.
  double tolerance_px = 4.0;
  // The frame's score (schedule/camera_degeneracy.h) on its agreeing tracks: fewer than min_tracks is D = 1,
  // reference_tracks or more adds nothing; the median error saturates its term at residual_threshold_px.
  int min_tracks = 20;
  double reference_tracks = 75;
  double residual_threshold_px = 4.0;
  // Shut at D > threshold, open again after release_frames frames at D <= threshold - release_margin.
  double threshold = 0.5;
  double release_margin = 0.1;
  int release_frames = 3;
  // After this long shut the frames are taken again whatever their score: meanwhile the IMU alone carried
  // the window (VIO) and its prediction drifted, which the tracks would otherwise be held against for good.
  double max_shut_s = 5.0;

  Status Validate() const;  // "schedule.<field>: ..."
};

struct VisualFactorConfig {
  FeatureTrackerConfig tracker;  // its min_track_length: observations before a feature becomes a landmark
  // With a second camera and its extrinsic in the data (a stereo rig): each frame's features are matched
  // in the right image of the same instant (visual/stereo_matcher.h), and the matches become factors and
  // the landmarks' first depth (providers/visual_provider.h).
  bool stereo = true;
  // Reprojection noise, pixels: KLT on a sharp 8-bit image is good to a few tenths; 1 px leaves room for
  // the undistortion and the rolling and global shutter's timing (VINS-Mono uses 1.5 px).
  double pixel_sigma_px = 1.0;
  // Huber loss on the residual in sigmas: a reprojection beyond this counts linearly.
  double huber_sigmas = 2.0;
  // Triangulation (visual/triangulation.h): the rays must span this angle, the point lie this far in front
  // of every camera and not farther than max_depth_m from its anchor (farther points constrain rotation
  // only, and their inverse depth is near zero where the linearization is poor).
  double min_parallax_deg = 1.0;
  double min_depth_m = 0.5;
  double max_depth_m = 150;
  // After each solve a landmark with an observation reprojecting worse than this, or a depth that left
  // [min_depth_m, max_depth_m], is dropped with its factors (a moving object, a bad track).
  double max_reprojection_px = 3.0;
  // LVIO: a landmark whose depth came from the LiDAR map stays on the map's plane where its anchor ray met
  // it (factors/landmark_plane_factor.h), under the Huber loss of huber_sigmas in the plane's sigmas; not
  // with estimate_extrinsic (the rays that met the planes turn as the extrinsic converges).
  bool hold_map_depth = true;
  // The camera time offset t_d (camera stamp + t_d = IMU time): the value to start from, and whether the
  // window estimates it (free, with a prior of time_offset_sigma_s about the start value).
  double time_offset_s = 0;
  bool estimate_time_offset = false;
  double time_offset_sigma_s = 0.05;
  // The camera extrinsic T_body_camera: held at the given one, or free in the window (estimate_extrinsic)
  // with a prior of extrinsic_rotation_sigma_deg and extrinsic_translation_sigma_m about it. The rotation is
  // observed wherever the body turns (simulated urban, LVIO, 12 s: 2 deg off -> 0.07 deg); the translation
  // needs rotations about more than one axis, which a car rarely makes: with a 5 cm prior it wandered 2.3 cm
  // from a true given one over the same 12 s, with 1 cm 1 mm, so the prior is a measured mount's 1 cm.
  bool estimate_extrinsic = false;
  double extrinsic_rotation_sigma_deg = 2;
  double extrinsic_translation_sigma_m = 0.01;
  // The window's solve with the camera (in place of wio.max_iterations and wio.max_solver_time_s): the
  // landmarks need 10-15 Levenberg-Marquardt iterations, and a window left short of its minimum is
  // marginalized as it stands, the prior carrying the shortfall on: on 60 s of simulated urban VIO with an
  // ideal IMU the drift is 3.7 % with 5, 1.15 % with 10, 0.88 % with 15 and 25 (docs/METHOD.md
  // "Visual-inertial odometry"). A node per 0.1 s; VIO takes ~45 ms per node on 2 loaded cores.
  int max_iterations = 15;
  double max_solver_time_s = 0.1;  // s
  // VIO's start: the IMU cannot tell rest from a constant velocity, the camera can. Rest (the static start)
  // needs the tracked features' mean image motion below this per frame on every node of the initialization
  // window (at rest it is the tracks' noise, ~0.01 px; a car at 1 m/s moves features by pixels per frame);
  // above it the visual-inertial start (init/visual_inertial_poses.h) runs instead.
  double max_static_flow_px = 0.5;  // px per frame
  VisualScheduleConfig schedule;

  Status Validate() const;
};

}  // namespace uf::estimator
