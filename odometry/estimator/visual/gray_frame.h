// Internal to uf_estimator_visual (OpenCV types; include only from its sources): a frame as the 8-bit gray
// image the front end works on, and its exposure normalization (docs/METHOD.md "Visual front end", step 0).
#pragma once

#include <opencv2/core.hpp>

#include "odometry/types/measurements.h"

namespace uf::estimator {

// A copy of an 8-bit gray or RGB image as gray.
cv::Mat GrayOf(const Image& image);

// Maps the frame to mean 128 and spread 50 DN (g' = a g + b, a within [1/8, 8]), so that Lucas-Kanade,
// which matches raw intensities, follows a global exposure or illumination change. A frame with less spread
// than min_contrast is left alone (its noise would be amplified).
void NormalizeExposure(cv::Mat& gray, double mean, double std_dev, double min_contrast);

}  // namespace uf::estimator
