// A simulated camera moving through a simulator scene, for the visual front-end tests: frames rendered at
// chosen times, and the ground truth of any pixel (the scene point its ray hits) and of any world point
// (the pixel it projects to at another time).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sensors/camera_renderer.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/sequence/sim_trajectory.h"
#include "odometry/sim/sequence/simulation_config.h"

namespace uf::estimator::test {

class SimulatedCamera {
 public:
  // The scene's default vehicle motion with the simulator's default forward-looking 640 x 480 camera,
  // changed by `adjust` when given (e.g. scripted darkness).
  static std::unique_ptr<SimulatedCamera> Create(
      const std::string& scene, double duration_s, std::uint64_t seed,
      const std::function<void(sim::CameraConfig&)>& adjust = nullptr) {
    auto out = std::unique_ptr<SimulatedCamera>(new SimulatedCamera);
    if (adjust) adjust(out->config_.camera.model);
    out->config_.scene = scene;
    out->config_.duration_s = duration_s;
    out->config_.seed = seed;
    auto motion = sim::MakeSimulationTrajectory(out->config_);
    EXPECT_TRUE(motion) << motion.error();
    if (!motion) return nullptr;
    out->motion_ = std::make_unique<sim::SimulationTrajectory>(std::move(*motion));
    auto built = sim::BuildScene(
        {scene, seed, out->motion_->scene_path, out->config_.body_height_m, out->config_.origin});
    EXPECT_TRUE(built) << built.error();
    if (!built) return nullptr;
    auto caster = sim::RayCaster::Create(*built);
    EXPECT_TRUE(caster) << caster.error();
    if (!caster) return nullptr;
    out->caster_ = std::make_unique<sim::RayCaster>(std::move(*caster));
    auto renderer =
        sim::CameraRenderer::Create(out->config_.camera.model, *out->caster_, out->motion_->spline,
                                    out->config_.camera.placement.T_body_sensor, seed);
    EXPECT_TRUE(renderer) << renderer.error();
    if (!renderer) return nullptr;
    out->renderer_ = std::make_unique<sim::CameraRenderer>(std::move(*renderer));
    return out;
  }

  // A second camera of the same model at T_left_right from the first (a stereo pair); RenderRight then
  // renders it.
  bool AddRightCamera(const SE3& T_left_right) {
    auto right =
        sim::CameraRenderer::Create(config_.camera.model, *caster_, motion_->spline,
                                    config_.camera.placement.T_body_sensor * T_left_right, config_.seed + 1);
    EXPECT_TRUE(right) << right.error();
    if (!right) return false;
    right_ = std::make_unique<sim::CameraRenderer>(std::move(*right));
    return true;
  }
  Image RenderRight(Stamp t) const {
    auto frame = right_->Render(t);
    EXPECT_TRUE(frame) << frame.error();
    return frame ? frame->image : Image{};
  }

  Stamp begin() const { return motion_->begin; }
  SE3 CameraPose(Stamp t) const { return renderer_->CameraPose(t); }
  const PinholeRadtan& model() const { return renderer_->model(); }

  Image Render(Stamp t) const {
    auto frame = renderer_->Render(t);
    EXPECT_TRUE(frame) << frame.error();
    return frame ? frame->image : Image{};
  }

  // The world point seen at `pixel` at time t; nullopt when the ray hits nothing.
  std::optional<Eigen::Vector3d> PointAt(Stamp t, const Eigen::Vector2d& pixel) const {
    return PointAlong(renderer_->CameraPose(t), model().Unproject(pixel));
  }
  // The world point the ray `ray_camera` (camera frame) from a camera at T_world_camera hits, or nullopt.
  std::optional<Eigen::Vector3d> PointAlong(const SE3& T_world_camera,
                                            const Eigen::Vector3d& ray_camera) const {
    const Eigen::Vector3d direction = (T_world_camera.so3() * ray_camera).normalized();
    sim::Ray ray{T_world_camera.translation().cast<float>(), direction.cast<float>()};
    const sim::RayHit hit = caster_->Cast(ray);
    if (!hit.hit()) return std::nullopt;
    return T_world_camera.translation() + static_cast<double>(hit.distance) * direction;
  }

  // Where a world point appears at time t; nullopt behind the camera.
  std::optional<Eigen::Vector2d> PixelOf(Stamp t, const Eigen::Vector3d& p_world) const {
    return model().Project(renderer_->CameraPose(t).inverse() * p_world);
  }

 private:
  SimulatedCamera() = default;

  sim::SimulationConfig config_;
  std::unique_ptr<sim::SimulationTrajectory> motion_;
  std::unique_ptr<sim::RayCaster> caster_;
  std::unique_ptr<sim::CameraRenderer> renderer_, right_;
};

}  // namespace uf::estimator::test
