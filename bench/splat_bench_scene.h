// The splat benchmarks' shared scene: a street of N flat Gaussians on surfaces (55 % ground z = 0 from 2 to
// 30 m ahead, 35 % side walls x = +-8 m up to 6 m, 10 % a far wall at y = 30 m; local z along the surface
// normal, tangent sizes 1-10 cm, SH degree 3), world frame z up, the street along +y; and the load average
// every figure is printed with.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include "splat/gaussian_model.h"
#include "splat/render_types.h"

namespace uf::bench {

inline std::string LoadAverage() {
  std::ifstream file("/proc/loadavg");
  std::string line;
  std::getline(file, line);
  return line;
}

inline uf::splat::GaussianModel StreetScene(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  uf::splat::GaussianModel model;
  model.sh_degree = 3;
  std::vector<float> sh(model.ShStride());
  for (std::size_t i = 0; i < n; ++i) {
    // Surface: 55% ground (z = 0), 35% side walls (x = +-8, z in [0, 6]), 10% far wall (y = 30).
    const float pick = uniform(rng);
    Eigen::Vector3f position, normal_axis;
    if (pick < 0.55f) {
      position = {-8 + 16 * uniform(rng), 2 + 28 * uniform(rng), 0};
      normal_axis = Eigen::Vector3f::UnitZ();
    } else if (pick < 0.9f) {
      position = {uniform(rng) < 0.5f ? -8.0f : 8.0f, 2 + 28 * uniform(rng), 6 * uniform(rng)};
      normal_axis = Eigen::Vector3f::UnitX();
    } else {
      position = {-8 + 16 * uniform(rng), 30, 6 * uniform(rng)};
      normal_axis = Eigen::Vector3f::UnitY();
    }
    // Local z along the surface normal (thin), x and y in the surface, spun about the normal.
    const Eigen::Quaternionf to_normal =
        Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), normal_axis);
    const Eigen::Quaternionf rotation = to_normal * Eigen::Quaternionf(Eigen::AngleAxisf(
                                                        6.2831853f * uniform(rng), Eigen::Vector3f::UnitZ()));
    const float s1 = 0.01f + 0.09f * uniform(rng), s2 = 0.01f + 0.09f * uniform(rng);
    const Eigen::Vector3f log_scale(std::log(s1), std::log(s2), std::log(0.2f * std::min(s1, s2)));
    for (int k = 0; k < model.ShStride(); ++k) sh[k] = k < 3 ? 1.2f * normal(rng) : 0.1f * normal(rng);
    model.Add(position, log_scale, rotation, 1.0f + normal(rng), sh.data());
  }
  return model;
}

// Camera 1.5 m above the street at y looking along +y (camera x = world x, y = -world z, z = world y), turned
// by yaw (rad) about the world z axis; focal length 0.8 x width.
inline uf::splat::SplatCamera StreetCamera(int width, int height, double y = 0, double yaw = 0) {
  uf::splat::SplatCamera camera;
  camera.pinhole = {.width = width,
                    .height = height,
                    .fx = 0.8 * width,
                    .fy = 0.8 * width,
                    .cx = 0.5 * width,
                    .cy = 0.5 * height};
  Eigen::Matrix3d R_world_camera;
  R_world_camera << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  camera.T_world_camera = uf::SE3(uf::SO3(turn * R_world_camera), Eigen::Vector3d(0, y, 1.5));
  return camera;
}

}  // namespace uf::bench
