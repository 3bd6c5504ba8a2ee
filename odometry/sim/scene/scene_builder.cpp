#include "odometry/sim/scene/scene_builder.h"

#include <array>
#include <cmath>
#include <string>

#include "odometry/sim/scene/scene_generators.h"
#include "odometry/sim/scene/scene_path.h"
#include "odometry/sim/scene/scene_placement.h"

namespace uf::sim {

namespace {

constexpr std::array<std::string_view, 5> kSceneNames = {"urban", "wild", "warehouse", "corridor", "tunnel"};

std::string NameList() {
  std::string out;
  for (const std::string_view name : kSceneNames) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

}  // namespace

std::span<const std::string_view> SceneNames() { return kSceneNames; }

double SceneClearance(std::string_view name) {
  if (name == "urban") return 3.0;
  if (name == "wild") return 2.5;
  if (name == "warehouse" || name == "corridor") return 1.1;
  if (name == "tunnel") return 4.0;
  return 0.0;
}

Expected<Scene> BuildScene(const SceneOptions& options) {
  using BuildFunction = void (*)(const ScenePath&, std::uint64_t, TriangleMesh&);
  BuildFunction build = nullptr;
  if (options.name == "urban") build = BuildUrban;
  if (options.name == "wild") build = BuildWild;
  if (options.name == "warehouse") build = BuildWarehouse;
  if (options.name == "corridor") build = BuildCorridor;
  if (options.name == "tunnel") build = BuildTunnel;
  if (build == nullptr) {
    return Status::Error("scene.name: unknown scene '" + options.name + "', expected one of: " + NameList());
  }
  const Trajectory& trajectory = options.trajectory;
  if (trajectory.size() < 2) {
    return Status::Error("scene.trajectory: needs at least 2 poses, got " +
                         std::to_string(trajectory.size()));
  }
  if (trajectory.stamps.size() != trajectory.poses.size()) {
    return Status::Error("scene.trajectory: needs one stamp per pose, got " +
                         std::to_string(trajectory.stamps.size()) + " stamps for " +
                         std::to_string(trajectory.poses.size()) + " poses");
  }
  if (!std::isfinite(options.body_height_m) || options.body_height_m < 0.0) {
    return Status::Error("scene.body_height_m: must be finite and >= 0, got " +
                         std::to_string(options.body_height_m));
  }
  if (Status s = ValidateGeodeticOrigin(options.origin); !s.ok())
    return Status::Error("scene." + s.message());
  Expected<ScenePath> path = ScenePath::FromTrajectory(trajectory, 1.0, options.body_height_m);
  if (!path.ok()) return path.status();

  Scene scene;
  scene.name = options.name;
  scene.origin = options.origin;
  build(*path, SubSeed(options.seed, options.name), scene.mesh);
  return scene;
}

}  // namespace uf::sim
