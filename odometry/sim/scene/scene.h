// A simulated world: one triangle mesh in a z-up world frame (x east, y north, z up, metres) with a
// material per triangle. Materials decide what the sensors see: the camera's colour (a procedural texture,
// see SurfaceColor) and the LiDAR's intensity (reflectivity).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/types/geodetic.h"

namespace uf::sim {

enum class Material : std::uint8_t {
  kAsphalt,
  kRoadMarking,
  kSidewalk,
  kConcrete,
  kBrick,
  kPlaster,
  kGlass,
  kCarPaint,
  kMetal,
  kBark,
  kFoliage,
  kGrass,
  kSoil,
  kRock,
  kShelfSteel,
  kCardboard,
  kTunnelLining,
  kCount,
};

struct MaterialAppearance {
  std::string_view name;
  Eigen::Vector3f base_rgb;  // linear RGB in [0, 1]
  float reflectivity;        // diffuse LiDAR reflectivity in [0, 1] (road ~0.1, marking ~0.6, retro-signs ~1)
};

const MaterialAppearance& AppearanceOf(Material material);

// Colour (linear RGB in [0, 1]) of the surface of `material` at world point p with unit normal n: the base
// colour modulated by a deterministic procedural texture (bricks, lane paint, bark, gravel, ...) whose
// detail is a few centimetres to a metre in size, so that image corners exist to be tracked. A pure function
// of its arguments.
Eigen::Vector3f SurfaceColor(Material material, const Eigen::Vector3d& p, const Eigen::Vector3f& n);

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;   // world frame, m
  std::vector<Eigen::Vector3i> triangles;  // vertex indices; counter-clockwise seen from the outside
  std::vector<Material> materials;         // one per triangle

  std::size_t triangle_count() const { return triangles.size(); }
};

struct Scene {
  std::string name;
  TriangleMesh mesh;
  // Where the world origin is on the Earth (for GNSS). The world frame is east-north-up at this point.
  GeodeticOrigin origin;
};

}  // namespace uf::sim
