// Procedural, seeded simulator worlds laid out along a body trajectory: BuildScene(options) returns a
// textured triangle mesh (see scene.h) for one of SceneNames(). The ground follows the trajectory's height
// (body z minus body_height_m) and objects keep a clearance from every trajectory sample, so any trajectory,
// including a recorded one, drives through a sensible world.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "odometry/sim/scene/scene.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::sim {

struct SceneOptions {
  std::string name;            // one of SceneNames()
  std::uint64_t seed = 1;      // same seed -> bit-identical mesh
  Trajectory trajectory;       // body trajectory T_world_body (z up), at least 2 stamped poses
  double body_height_m = 1.8;  // height of the body (IMU) frame above the ground along the trajectory, >= 0
  GeodeticOrigin origin = {49.0069, 8.4037, 115.0};  // of the world frame (ENU) on the WGS84 ellipsoid
};

// {"urban", "wild", "warehouse", "corridor", "tunnel"}.
std::span<const std::string_view> SceneNames();

// Builds the scene. Errors: unknown name (the message lists the names), fewer than 2 poses, poses without
// stamps, non-finite poses, body_height_m < 0 or non-finite, an invalid origin (ValidateGeodeticOrigin).
Expected<Scene> BuildScene(const SceneOptions& options);

// The xy clearance (m) kept between the trajectory and every object of a scene other than its ground, road
// or floor (urban 3.0, wild 2.5, warehouse 1.1, corridor 1.1, tunnel 4.0); 0 for an unknown name.
double SceneClearance(std::string_view name);

}  // namespace uf::sim
