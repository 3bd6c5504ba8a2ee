// The overlay `ultrafusion colorize --overlay` writes: the camera image with every visible projected LiDAR
// point drawn as a small square coloured by its depth, for judging a LiDAR-camera calibration by eye
// (outlines of the projected depth should sit on the image's outlines).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "mapping/colorize_projection.h"
#include "odometry/types/measurements.h"

namespace uf::pipeline {

// The depth range the colour map spans.
struct DepthRange {
  float near_m = 0, far_m = 0;
};

// The 5th and 95th percentiles of the visible points' depths (robust to a few stray near or far points);
// {0, 0} when no point is visible.
DepthRange VisibleDepthRange(const mapping::ProjectedScan& scan);

// Colour map: t = clamp((depth - near) / (far - near), 0, 1) picks the hue h = 240 deg * t at full
// saturation and value, so near = red (0 deg), then yellow, green, cyan, far = blue (240 deg).
std::array<std::uint8_t, 3> DepthColor(float depth, const DepthRange& range);

// The image as RGB with the visible points drawn, farthest first so nearer points stay on top, each as a
// square of (2 r + 1) pixels a side, r = max(1, round(width / 1000)).
Image RenderDepthOverlay(const Image& image, const mapping::ProjectedScan& scan, const DepthRange& range);

}  // namespace uf::pipeline
