// The visual front end (docs/METHOD.md "Visual front end"): Shi-Tomasi corners tracked frame to frame by
// pyramidal Lucas-Kanade, each track checked forward-backward and against a fundamental matrix fitted by
// RANSAC, new corners detected at least min_distance_px from the tracks kept (longer tracks win), an optional
// mask (the ego vehicle), and keyframes chosen by parallax. Pixels are undistorted through the project's
// camera model, so the epipolar check and the parallax are measured in a distortion-free pinhole with the
// camera's fx, fy, cx, cy.
//
// Per frame it reports the statistics the reliability scheduling scores a camera by (docs/METHOD.md
// "Factor-wise reliability scheduling"): feature count, tracked ratio, 8x8 grid occupancy, forward-backward
// and RANSAC losses and the inliers' epipolar (Sampson) error. The estimator's reprojection error belongs to
// the visual factor, which does not exist yet.
//
// Bad frames (black, saturated, textureless) are tracked as they are, with a warning on the frame; a frame
// whose stamp is not after the previous one, or whose size or channels do not match, is refused and leaves
// the tracker as it was.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "odometry/estimator/config/feature_tracker_config.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct TrackedFeature {
  long id = 0;                     // unique over the tracker's life
  int length = 1;                  // frames it was seen in, this one included
  Eigen::Vector2d pixel;           // where it is in the image as recorded (distorted)
  Eigen::Vector2d previous_pixel;  // where it was in the previous frame (= pixel when length is 1)
  Eigen::Vector2d normalized;      // undistorted (x/z, y/z) of its ray
  // Image-plane velocity of `normalized` per second since the previous frame (zero when new): the
  // visual factor's time-offset compensation needs it.
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
};

struct FrameTrackStats {
  Stamp stamp = 0;
  int features = 0;              // after this frame: tracked + detected
  int tracked = 0;               // carried over from the previous frame
  int detected = 0;              // new corners
  int lost_klt = 0;              // Lucas-Kanade found no match, or it left the image or the mask
  int lost_fb = 0;               // failed the forward-backward check
  int lost_ransac = 0;           // outliers of the fundamental matrix
  int lost_spacing = 0;          // dropped for lying closer than min_distance_px to a longer track
  double tracked_ratio = 0;      // tracked / the previous frame's features (0 on the first frame)
  double grid_occupancy = 0;     // share of the grid cells holding at least one feature
  double epipolar_error_px = 0;  // mean Sampson distance of the RANSAC inliers (0 without a fit)
  double parallax_px = 0;        // mean undistorted displacement since the last keyframe
  double mean_intensity = 0, intensity_std = 0;  // of the frame, digital numbers
  bool keyframe = false;
  double time_ms = 0;   // tracking time of this frame
  std::string warning;  // why the frame is poor ("dark", "saturated", "textureless"); empty if not
};

struct TrackedFrame {
  Stamp stamp = 0;
  std::vector<TrackedFeature> features;
  FrameTrackStats stats;
};

class FeatureTracker {
 public:
  // `mask` (optional, empty for none): 8-bit gray of the camera's size; features only where it is non-zero.
  // Fails for an invalid config, invalid intrinsics or a mask of the wrong size or channels.
  static Expected<FeatureTracker> Create(const CameraModel& camera, const FeatureTrackerConfig& config,
                                         const Image& mask = {});

  FeatureTracker(FeatureTracker&&) noexcept;
  FeatureTracker& operator=(FeatureTracker&&) noexcept;
  ~FeatureTracker();

  // Tracks the features into `image` (8-bit gray or RGB) taken at `stamp`. Fails, leaving the tracker as it
  // was, when the stamp is not after the previous frame's or the image is not the camera's size.
  Expected<TrackedFrame> Track(Stamp stamp, const Image& image);

  const FeatureTrackerConfig& config() const;

 private:
  struct Impl;
  explicit FeatureTracker(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::estimator
