// Internal to uf_estimator_visual (OpenCV types; include only from its sources): a frame as the 8-bit gray
// image the front end works on, its exposure normalization (docs/METHOD.md "Visual front end", step 0), and
// the checks the tracker and the stereo matcher share.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"

namespace uf::estimator {

// A copy of an 8-bit gray or RGB image as gray.
cv::Mat GrayOf(const Image& image);

// Maps the frame to mean 128 and spread 50 DN (g' = a g + b, a within [1/8, 8]), so that Lucas-Kanade,
// which matches raw intensities, follows a global exposure or illumination change. A frame with less spread
// than min_contrast is left alone (its noise would be amplified).
void NormalizeExposure(cv::Mat& gray, double mean, double std_dev, double min_contrast);

// Gaussian smoothing of sigma_px (feature_tracker_config.h); none at 0.
void Smooth(cv::Mat& gray, double sigma_px);

// Whether the image is 8-bit gray or RGB of the camera's size, its pixel buffer complete.
bool FitsCamera(const Image& image, const CameraModel& camera);

// The undistorted normalized coordinates (x/z, y/z) of a pixel's ray; nullopt for a ray at or beyond ~89 deg
// from the optical axis (a fisheye's rim), which has none.
std::optional<Eigen::Vector2d> NormalizedRay(const CameraModel& camera, const Eigen::Vector2d& pixel);

}  // namespace uf::estimator
