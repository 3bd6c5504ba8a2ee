// Indoor scenes. warehouse: a concrete floor, walls and a ceiling with beams enclosing the track's bounding
// box plus a margin, and rows of pallet racks (steel uprights and beams, cardboard boxes on several levels)
// on both sides of the track, forming aisles. corridor: a 2.5 m wide, 3 m high rectangular tube swept along
// the track (plaster walls, concrete floor and ceiling), featureless, open ends 60 m beyond the track.
#include <algorithm>
#include <cmath>
#include <random>

#include "odometry/sim/scene/mesh_builder.h"
#include "odometry/sim/scene/scene_generators.h"
#include "odometry/sim/scene/scene_placement.h"

namespace uf::sim {

namespace {

constexpr double kAisleHalfWidth = 1.6;  // free half width between rack fronts (m)
constexpr double kBayLength = 2.7;       // rack bay along the aisle
constexpr double kBayHalfDepth = 0.55;
constexpr double kLevelSpacing = 1.6;      // vertical distance between beam levels
constexpr double kEnclosureMargin = 12.0;  // walls this far outside the track's bounding box
constexpr double kCeilingAboveFloor = 9.0;

// One rack bay centred at (center.xy, floor z) with yaw: 4 uprights, front/back beams per level, boxes.
void AddBay(const Eigen::Vector3d& center, double yaw, int levels, std::mt19937_64& rng,
            MeshBuilder& builder) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  auto at = [&](double x, double y, double z) {
    return Eigen::Vector3d(center.x() + c * x - s * y, center.y() + s * x + c * y, center.z() + z);
  };
  const double height = levels * kLevelSpacing + 0.3, hx = 0.5 * kBayLength - 0.04, hy = kBayHalfDepth - 0.04;
  for (const double x : {-hx, hx}) {
    for (const double y : {-hy, hy}) {
      builder.AddBox(at(x, y, 0.5 * height - 0.05), {0.04, 0.04, 0.5 * height + 0.05}, yaw,
                     Material::kShelfSteel);
    }
  }
  for (int level = 0; level <= levels; ++level) {
    const double z = level * kLevelSpacing + 0.15;
    if (level > 0) {
      for (const double y : {-hy, hy})
        builder.AddBox(at(0, y, z - 0.06), {hx, 0.03, 0.06}, yaw, Material::kShelfSteel);
    }
    if (level == levels) break;
    // Boxes standing on this level, packed along the bay with gaps.
    for (double x = -hx + 0.1; x < hx - 0.4;) {
      const double w = Uniform(rng, 0.4, 0.9), d = Uniform(rng, 0.5, 1.0), h = Uniform(rng, 0.3, 1.2);
      if (x + w > hx - 0.05) break;
      if (Chance(rng, 0.75)) {
        builder.AddBox(at(x + 0.5 * w, Uniform(rng, -0.05, 0.05), z + 0.5 * h),
                       {0.5 * w, 0.5 * std::min(d, 2.0 * hy - 0.1), 0.5 * h}, yaw, Material::kCardboard);
      }
      x += w + Uniform(rng, 0.05, 0.3);
    }
  }
}

}  // namespace

void BuildWarehouse(const ScenePath& path, std::uint64_t seed, TriangleMesh& mesh) {
  std::mt19937_64 rng(seed);
  MeshBuilder builder(mesh);
  // Floor over the whole enclosure, following the track's height.
  AddGround(
      path, kEnclosureMargin, 1e9, 2.0, 0.0, [](double, double, double) { return 0.0; },
      [](double, double, double, double) { return Material::kConcrete; }, mesh);
  double z_min = path.samples().front().position.z(), z_max = z_min;
  for (const auto& sample : path.samples()) {
    z_min = std::min(z_min, sample.position.z());
    z_max = std::max(z_max, sample.position.z());
  }
  const double bottom = z_min - path.body_height() - 1.0;
  const double top = z_max - path.body_height() + kCeilingAboveFloor;
  const Eigen::Vector2d lo = path.min_xy().array() - kEnclosureMargin,
                        hi = path.max_xy().array() + kEnclosureMargin;
  // Walls facing inwards (counter-clockwise seen from inside) and the ceiling facing down.
  const Eigen::Vector3d a(lo.x(), lo.y(), bottom), b(hi.x(), lo.y(), bottom), c(hi.x(), hi.y(), bottom),
      d(lo.x(), hi.y(), bottom), up(0, 0, top - bottom);
  builder.AddQuad(a, a + up, b + up, b, Material::kConcrete);
  builder.AddQuad(b, b + up, c + up, c, Material::kConcrete);
  builder.AddQuad(c, c + up, d + up, d, Material::kConcrete);
  builder.AddQuad(d, d + up, a + up, a, Material::kConcrete);
  builder.AddQuad(a + up, d + up, c + up, b + up, Material::kMetal);
  for (double x = lo.x() + 3.0; x < hi.x(); x += 6.0) {  // roof beams
    builder.AddBox({x, 0.5 * (lo.y() + hi.y()), top - 0.3}, {0.15, 0.5 * (hi.y() - lo.y()), 0.3}, 0.0,
                   Material::kShelfSteel);
  }
  // Racks: two back-to-back rows on each side of the aisle, bays along the track, a cross aisle every 5-8
  // bays. A bay is dropped if it comes within the clearance of the track or overlaps another bay.
  Placer placer(path, 1.1);
  for (const double side : {1.0, -1.0}) {
    for (int row = 0; row < 2; ++row) {
      const double lateral = side * (kAisleHalfWidth + kBayHalfDepth + row * (2.0 * kBayHalfDepth + 0.2));
      int until_gap = static_cast<int>(Uniform(rng, 5.0, 9.0));
      for (double s = 0.5 * kBayLength; s < path.length(); s += kBayLength) {
        const int levels = static_cast<int>(Uniform(rng, 2.0, 5.0));
        if (--until_gap == 0) {
          until_gap = static_cast<int>(Uniform(rng, 5.0, 9.0));
          s += 0.3 * kBayLength;
          continue;
        }
        const Eigen::Vector3d center = path.GroundPoint(s, lateral);
        const double yaw = path.At(s).heading;
        if (!placer.TryPlace(RectFootprint(center.head<2>(), 0.5 * kBayLength, kBayHalfDepth, yaw))) continue;
        AddBay(center, yaw, levels, rng, builder);
      }
    }
  }
}

void BuildCorridor(const ScenePath& track, std::uint64_t /*seed*/, TriangleMesh& mesh) {
  const ScenePath path = track.Extended(60.0);
  // Closed profile in (left, up): floor left to right, right wall up, ceiling right to left, left wall
  // down, so that every face points into the corridor (see AddSweptProfile).
  MeshBuilder(mesh).AddSweptProfile(
      path.GroundPolyline(0.0, path.length()), {{1.25, 0.0}, {-1.25, 0.0}, {-1.25, 3.0}, {1.25, 3.0}},
      {Material::kConcrete, Material::kPlaster, Material::kConcrete, Material::kPlaster}, true);
}

}  // namespace uf::sim
