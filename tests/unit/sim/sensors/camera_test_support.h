// Helpers of the camera tests: still trajectories, a camera looking along world +x, sRGB decoding to linear
// grey (independent of the renderer's tables), and renderer/frame shortcuts that report failures.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "odometry/sim/sensors/camera_renderer.h"
#include "odometry/sim/sensors/ray_caster.h"

namespace uf::sim::camera_test {

inline constexpr Stamp kSecond = kNanosecondsPerSecond;

// A body standing still at T_world_body for [0, 10] s.
inline TrajectorySpline StaticTrajectory(const SE3& T_world_body = SE3()) {
  return TrajectorySpline::FromControlPoints(-kSecond, kSecond, std::vector<SE3>(14, T_world_body));
}

// Camera axes (x right, y down, z forward) looking along world +x with world z up: R_body_camera has the
// camera axes as columns, x_cam = -y_world, y_cam = -z_world, z_cam = +x_world.
inline SE3 LookAlongX(const Eigen::Vector3d& position = Eigen::Vector3d::Zero()) {
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return SE3(SO3(R), position);
}

// sRGB 8-bit value to linear (the standard decoding, independent of the renderer's table).
inline double SrgbToLinear(std::uint8_t dn) {
  const double c = dn / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Mean of the three channels in linear units, per pixel, as a float image.
inline cv::Mat LinearGray(const Image& image) {
  cv::Mat gray(image.height, image.width, CV_32F);
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) {
      const std::uint8_t* p = &image.pixels[3 * (static_cast<std::size_t>(v) * image.width + u)];
      gray.at<float>(v, u) =
          static_cast<float>((SrgbToLinear(p[0]) + SrgbToLinear(p[1]) + SrgbToLinear(p[2])) / 3);
    }
  }
  return gray;
}

inline double MeanLinear(const Image& image) { return cv::mean(LinearGray(image))[0]; }

inline CameraRenderer MakeRenderer(const CameraConfig& config, const RayCaster& caster,
                                   const TrajectorySpline& spline, const SE3& T_body_camera,
                                   std::uint64_t seed = 7) {
  auto renderer = CameraRenderer::Create(config, caster, spline, T_body_camera, seed);
  EXPECT_TRUE(renderer.ok()) << (renderer.ok() ? "" : renderer.error());
  return std::move(renderer).value();
}

inline Image RenderImage(const CameraRenderer& renderer, Stamp t) {
  auto frame = renderer.Render(t);
  EXPECT_TRUE(frame.ok()) << (frame.ok() ? "" : frame.error());
  return frame.ok() ? frame->image : Image();
}

}  // namespace uf::sim::camera_test
