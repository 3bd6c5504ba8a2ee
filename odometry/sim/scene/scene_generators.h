// The per-scene generators behind BuildScene (internal to uf_sim_scene). Each appends its world to `mesh`,
// laid out along `path` (ground = body z - body height), drawing from std::mt19937_64 seeded with `seed`.
#pragma once

#include <cstdint>
#include <functional>

#include "odometry/sim/scene/scene.h"
#include "odometry/sim/scene/scene_path.h"

namespace uf::sim {

void BuildUrban(const ScenePath& path, std::uint64_t seed, TriangleMesh& mesh);
void BuildWild(const ScenePath& path, std::uint64_t seed, TriangleMesh& mesh);
void BuildWarehouse(const ScenePath& path, std::uint64_t seed, TriangleMesh& mesh);
void BuildCorridor(const ScenePath& path, std::uint64_t seed, TriangleMesh& mesh);
void BuildTunnel(const ScenePath& path, std::uint64_t seed, TriangleMesh& mesh);

// Ground heightfield over the track's bounding box grown by `margin` m, cells of `cell` m (grown so that
// there are at most ~300k cells): vertex height GroundHeight(x, y) + relief(x, y, d) with d the xy distance
// to the track, material per cell from material(x, y, d, slope) at the cell centre (slope = |gradient|);
// cells with no corner within `keep_within` of the track, or (skip_within > 0) all corners within
// skip_within of it, are left out.
void AddGround(const ScenePath& path, double margin, double keep_within, double cell, double skip_within,
               const std::function<double(double x, double y, double d)>& relief,
               const std::function<Material(double x, double y, double d, double slope)>& material,
               TriangleMesh& mesh);

}  // namespace uf::sim
