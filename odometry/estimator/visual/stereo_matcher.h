// Stereo matching of the visual front end (docs/METHOD.md "Visual front end"): the left camera's features
// found in the right image of the same instant, and their depth from the calibrated baseline.
//
// Each feature is tracked from the left image into the right one by pyramidal Lucas-Kanade (starting at its
// left pixel) and back; kept when the backward pass lands within max_fb_error_px and when the pair fits the
// epipolar geometry of the given extrinsic: with T_right_left = (R, t) and normalized rays x_l, x_r, the
// essential matrix E = [t]x R gives x_r^T E x_l = 0, and the pair's Sampson distance to it, scaled to pixels
// by the right camera's focal length, must stay within max_epipolar_px. The depth (left camera z) is the
// two-ray triangulation (triangulation.h), refused behind the cameras.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct StereoConfig {
  int klt_window_px = 21;  // larger than tracking's: the baseline's disparity is larger
  int klt_pyramid_levels = 4;
  double max_fb_error_px = 1.0;
  double max_epipolar_px = 1.5;  // Sampson distance to the extrinsic's epipolar geometry, right pixels
  double min_depth_m = 0.1;
};

struct StereoMatch {
  long id = 0;                  // the left feature's
  Eigen::Vector2d right_pixel;  // distorted, as recorded
  Eigen::Vector2d right_normalized;
  double epipolar_px = 0;  // the pair's Sampson distance, right pixels
  double depth_m = 0;      // z in the left camera
};

struct StereoStats {
  int features = 0, matched = 0;
  int lost_klt = 0, lost_fb = 0, lost_epipolar = 0, lost_depth = 0;
  double epipolar_px = 0;  // mean over the matches
};

struct StereoResult {
  std::vector<StereoMatch> matches;
  StereoStats stats;
};

// Fails for an invalid config or intrinsics, a right image that is not the right camera's size, or a
// non-finite extrinsic. T_left_right: the right camera in the left camera's frame (p_left = T p_right).
Expected<StereoResult> MatchStereo(const std::vector<TrackedFeature>& left_features, const Image& left,
                                   const Image& right, const CameraModel& left_camera,
                                   const CameraModel& right_camera, const SE3& T_left_right,
                                   const StereoConfig& config = {});

}  // namespace uf::estimator
