// What the Vulkan-against-reference tests share: a camera, n random Gaussians in front of it, and one
// renderer per test suite (creating a device takes a while on lavapipe).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "splat/gaussian_model.h"
#include "splat/render_types.h"
#include "splat/splat_renderer.h"

namespace uf::splat::testing {

inline SplatCamera Camera(int width, int height, const SE3& T_world_camera) {
  SplatCamera camera;
  camera.pinhole = {.width = width,
                    .height = height,
                    .fx = 0.9 * width,
                    .fy = 0.9 * width,
                    .cx = 0.5 * width - 0.3,
                    .cy = 0.5 * height + 0.2};
  camera.T_world_camera = T_world_camera;
  return camera;
}

// n Gaussians in front of the camera (depth 1.5-12 m, every 25th behind it), sizes 2-40 cm, random
// (unnormalized) rotations, opacities and SH coefficients of the given degree.
inline GaussianModel RandomScene(std::uint64_t seed, int n, int sh_degree, const SplatCamera& camera) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  GaussianModel model;
  model.sh_degree = sh_degree;
  std::vector<float> sh(model.ShStride());
  for (int i = 0; i < n; ++i) {
    const float z = i % 25 == 0 ? -2.0f : 1.5f + 10.5f * uniform(rng);
    const float x = (uniform(rng) * 1.4f - 0.7f) * z, y = (uniform(rng) * 1.0f - 0.5f) * z;
    const Eigen::Vector3d p_world = camera.T_world_camera * Eigen::Vector3d(x, y, z);
    Eigen::Vector3f log_scale;
    for (int a = 0; a < 3; ++a) log_scale[a] = std::log(0.02f + 0.38f * uniform(rng));
    const Eigen::Quaternionf q(normal(rng), normal(rng), normal(rng), normal(rng));
    for (int k = 0; k < model.ShStride(); ++k) sh[k] = (k < 3 ? 1.0f : 0.3f) * normal(rng);
    model.Add(p_world.cast<float>(), log_scale, q, 3.0f * normal(rng), sh.data());
  }
  return model;
}

class SharedRendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    Expected<std::unique_ptr<SplatRenderer>> created = SplatRenderer::Create();
    ASSERT_TRUE(created.ok()) << created.error();
    renderer_ = std::move(created.value());
  }
  static void TearDownTestSuite() { renderer_.reset(); }
  static inline std::unique_ptr<SplatRenderer> renderer_;
};

}  // namespace uf::splat::testing
