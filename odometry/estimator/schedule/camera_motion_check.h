// The camera's reliability check in the window (docs/METHOD.md "Factor-wise reliability scheduling", camera
// scheduling; paper Sec. III-D): before a frame's observations join the window, each of its tracks is held
// against the motion the window predicts between the track's previous node j and the frame's node k
// (T_k_j: camera k from camera j, so X_k = R X_j + t). A static point's track agrees with it when
//   - the rotation alone explains it: |pi(R x_j) - x_k| f <= tolerance (far points, little translation), or
//   - it lies on its epipolar line and in front of both cameras: the Sampson distance of x_k^T [t]x R x_j
//     (times the focal length f) <= tolerance, and the depths (z_k, z_j) solving z_k x_k - z_j R x_j = t in
//     least squares are both positive (a point moving against the translation's flow, e.g. on an object
//     crossing the view, would lie behind the camera).
// Its error is the smaller of the two that apply. A frame is then scored with the paper's weighted sum
// (schedule/camera_degeneracy.h) on its agreeing tracks, their 8x8 grid occupancy and the median error of
// every checked track; an activation gate with hysteresis (schedule/activation_gate.h) decides whether its
// observations join the window.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/estimator/schedule/camera_degeneracy.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

struct TrackMotionCheck {
  double error_px = 0;  // disagreement with the predicted motion (see above)
  bool agrees = false;
};

// x_j, x_k: the track's normalized coordinates at nodes j and k.
TrackMotionCheck CheckTrackMotion(const Eigen::Vector2d& x_j, const Eigen::Vector2d& x_k, const SE3& T_k_j,
                                  double focal_px, double tolerance_px);

// One checked track of a frame: its pixel (for the grid) and its check.
struct CheckedTrack {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  TrackMotionCheck check;
};

// The frame's score from its checked tracks (image width x height px, grid_cells per side); `active` left
// true (the gate's to set).
CameraCheck ScoreCameraMotion(Stamp stamp, const std::vector<CheckedTrack>& tracks, int width, int height,
                              int grid_cells, const CameraScoreConfig& config);

}  // namespace uf::estimator
