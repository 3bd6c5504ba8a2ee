// Open uneven terrain: an fBm heightfield that is flat along the track (so the trajectory's height fits:
// ground = body z - body height) and rises to a few metres of relief away from it, grass/soil/rock by slope
// and noise, a dirt track under the path, and sparse conifers, broadleaf trees and rocks.
#include <algorithm>
#include <cmath>
#include <random>

#include "odometry/sim/scene/lattice_noise.h"
#include "odometry/sim/scene/mesh_builder.h"
#include "odometry/sim/scene/scene_generators.h"
#include "odometry/sim/scene/scene_placement.h"

namespace uf::sim {

namespace {

constexpr double kFlatWithin = 3.0;     // relief is zero up to this distance from the track (m)
constexpr double kFullReliefAt = 25.0;  // full relief from this distance on
constexpr double kAmplitude = 4.0;      // relief = kAmplitude * (2 fbm - 1) * blend, m
constexpr double kMargin = 60.0;

// Relief above the track's ground level at (x, y), d m from the track: fBm (40 m cells, 5 octaves) times a
// C1 smoothstep blend b(t) = t^2 (3 - 2t), t = (d - kFlatWithin) / (kFullReliefAt - kFlatWithin) in [0, 1].
double Relief(double x, double y, double d, std::uint32_t salt) {
  const double t = std::clamp((d - kFlatWithin) / (kFullReliefAt - kFlatWithin), 0.0, 1.0);
  const double blend = t * t * (3.0 - 2.0 * t);
  if (blend == 0.0) return 0.0;
  return kAmplitude * (2.0 * noise::Fbm(x, y, 40.0, 5, salt) - 1.0) * blend;
}

}  // namespace

void BuildWild(const ScenePath& track, std::uint64_t seed, TriangleMesh& mesh) {
  const ScenePath path = track.Extended(30.0);
  std::mt19937_64 rng(seed);
  const auto salt = static_cast<std::uint32_t>(SplitMix64(seed));
  auto relief = [salt](double x, double y, double d) { return Relief(x, y, d, salt); };
  AddGround(
      path, kMargin, kMargin, 1.0, 0.0, relief,
      [salt](double x, double y, double d, double slope) {
        if (d < 1.8) return Material::kSoil;  // the dirt track
        if (slope > 0.6) return Material::kRock;
        return noise::Fbm(x, y, 6.0, 3, salt + 7) > 0.62 ? Material::kSoil : Material::kGrass;
      },
      mesh);
  auto ground_at = [&](const Eigen::Vector2d& xy) {
    const ScenePath::Nearest nearest = path.NearestPoint(xy.x(), xy.y());
    return nearest.z - path.body_height() + relief(xy.x(), xy.y(), nearest.distance);
  };

  MeshBuilder builder(mesh);
  Placer placer(path, 2.5);
  const Eigen::Vector2d lo = path.min_xy().array() - 50.0, hi = path.max_xy().array() + 50.0;
  // Trees on a jittered 10 m lattice, 30 % occupied; within 50 m of the track.
  for (double gx = lo.x(); gx < hi.x(); gx += 10.0) {
    for (double gy = lo.y(); gy < hi.y(); gy += 10.0) {
      const bool tree = Chance(rng, 0.3);
      const Eigen::Vector2d xy(gx + Uniform(rng, 0.0, 10.0), gy + Uniform(rng, 0.0, 10.0));
      const bool conifer = Chance(rng, 0.5);
      const double height = Uniform(rng, 4.0, 12.0), crown = Uniform(rng, 1.2, 3.0);
      const std::uint64_t blob_seed = rng();
      if (!tree || path.NearestPoint(xy.x(), xy.y()).distance > 50.0) continue;
      if (!placer.TryPlace(CircleFootprint(xy, crown), false)) continue;
      if (!placer.TryPlace(CircleFootprint(xy, 0.3))) continue;
      const Eigen::Vector3d base(xy.x(), xy.y(), ground_at(xy) - 0.3);
      const double trunk_radius = 0.05 + 0.02 * height;
      if (conifer) {
        builder.AddCylinder(base, trunk_radius, 0.35 * height, 6, Material::kBark);
        builder.AddCone(base + Eigen::Vector3d(0, 0, 0.25 * height), crown, 0.5 * height, 9,
                        Material::kFoliage);
        builder.AddCone(base + Eigen::Vector3d(0, 0, 0.55 * height), 0.7 * crown, 0.45 * height, 9,
                        Material::kFoliage);
      } else {
        builder.AddCylinder(base, trunk_radius, 0.6 * height, 7, Material::kBark);
        builder.AddBlob(base + Eigen::Vector3d(0, 0, 0.6 * height + 0.5 * crown), {crown, crown, 0.8 * crown},
                        2, 0.25, blob_seed, Material::kFoliage);
      }
    }
  }
  // Rocks on a jittered 7 m lattice, 25 % occupied, half buried.
  for (double gx = lo.x(); gx < hi.x(); gx += 7.0) {
    for (double gy = lo.y(); gy < hi.y(); gy += 7.0) {
      const bool rock = Chance(rng, 0.25);
      const Eigen::Vector2d xy(gx + Uniform(rng, 0.0, 7.0), gy + Uniform(rng, 0.0, 7.0));
      const double r = Uniform(rng, 0.3, 1.5);
      const Eigen::Vector3d radii(r * Uniform(rng, 0.8, 1.2), r * Uniform(rng, 0.8, 1.2),
                                  r * Uniform(rng, 0.4, 0.7));
      const std::uint64_t blob_seed = rng();
      if (!rock || path.NearestPoint(xy.x(), xy.y()).distance > 50.0) continue;
      if (!placer.TryPlace(CircleFootprint(xy, 1.3 * radii.head<2>().maxCoeff()))) continue;
      builder.AddBlob({xy.x(), xy.y(), ground_at(xy) + 0.2 * radii.z()}, radii, r > 0.8 ? 2 : 1, 0.3,
                      blob_seed, Material::kRock);
    }
  }
}

}  // namespace uf::sim
