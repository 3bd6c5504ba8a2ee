// The urban street canyon: a road ribbon centred on the track, curbs and sidewalks, buildings with windows,
// parked cars, poles and trees on both sides, and a ground plane beyond. Lateral offsets are measured to the
// left (+) of the track; "ground" is the track's body z minus the body height.
#include <cmath>
#include <numbers>
#include <random>

#include "odometry/sim/scene/mesh_builder.h"
#include "odometry/sim/scene/scene_generators.h"
#include "odometry/sim/scene/scene_placement.h"

namespace uf::sim {

namespace {

constexpr double kRoadHalfWidth = 5.5;   // two 3.5 m lanes (lines at +-3.4 m) plus 2 m parking strips
constexpr double kSidewalkOuter = 8.5;   // sidewalk from the curb at 5.5 m to 8.5 m
constexpr double kCurbHeight = 0.12;     // sidewalk top above the road
constexpr double kBuildingFront = 9.0;   // facade line
constexpr double kMarkingHeight = 0.01;  // road paint above the asphalt
constexpr double kExtension = 60.0;      // road continues this far beyond both ends of the track

// Local (x along the heading, y to the left) offset of a placement frame to world xy.
Eigen::Vector3d Local(const ScenePath::Sample& frame, double x, double y, double z) {
  const double c = std::cos(frame.heading), s = std::sin(frame.heading);
  return {frame.position.x() + c * x - s * y, frame.position.y() + s * x + c * y, z};
}

void AddRoad(const ScenePath& path, MeshBuilder& builder) {
  const std::vector<Eigen::Vector3d> line = path.GroundPolyline(0.0, path.length());
  // Left outer edge up, sidewalk, curb down, road, curb up, sidewalk, right outer edge down: walked from
  // left to right so that every top surface faces up (see AddSweptProfile).
  const double w = kRoadHalfWidth, o = kSidewalkOuter, h = kCurbHeight;
  builder.AddSweptProfile(line,
                          {{o, -0.1}, {o, h}, {w, h}, {w, 0.0}, {-w, 0.0}, {-w, h}, {-o, h}, {-o, -0.1}},
                          {Material::kConcrete, Material::kSidewalk, Material::kConcrete, Material::kAsphalt,
                           Material::kConcrete, Material::kSidewalk, Material::kConcrete});
  // Solid lane edge lines at +-3.4 m and a dashed centre line (3 m dashes every 9 m), 15 cm wide.
  const std::vector<Eigen::Vector3d> paint = path.GroundPolyline(0.0, path.length(), kMarkingHeight);
  for (const double y : {3.4, -3.4}) {
    builder.AddSweptProfile(paint, {{y + 0.075, 0.0}, {y - 0.075, 0.0}}, {Material::kRoadMarking});
  }
  for (double s = 0.0; s + 3.0 <= path.length(); s += 9.0) {
    builder.AddSweptProfile(path.GroundPolyline(s, s + 3.0, kMarkingHeight), {{0.075, 0.0}, {-0.075, 0.0}},
                            {Material::kRoadMarking});
  }
}

void AddBuildings(const ScenePath& path, double side, std::mt19937_64& rng, Placer& placer,
                  MeshBuilder& builder) {
  constexpr Material kFacades[] = {Material::kBrick, Material::kPlaster, Material::kConcrete};
  for (double s = Uniform(rng, 0.0, 6.0); s < path.length();) {
    const double width = Uniform(rng, 8.0, 25.0), depth = Uniform(rng, 8.0, 16.0);
    const double height = Uniform(rng, 6.0, 25.0);
    const Material facade = kFacades[static_cast<int>(Uniform(rng, 0.0, 3.0))];
    const double protrusion = Chance(rng, 0.5) ? 0.02 : 0.08;
    const ScenePath::Sample frame = path.At(s + 0.5 * width);
    const double ground = frame.position.z() - path.body_height();
    const double lateral = side * (kBuildingFront + 0.5 * depth);
    const Eigen::Vector3d center =
        Local(frame, 0.0, lateral, ground + 0.5 * height - 0.5);  // 1 m below ground
    if (placer.TryPlace(RectFootprint(center.head<2>(), 0.5 * width, 0.5 * depth, frame.heading))) {
      builder.AddBox(center, {0.5 * width, 0.5 * depth, 0.5 * height + 0.5}, frame.heading, facade);
      // Windows on the facade facing the road (local y = -side * depth / 2), floors every 3.2 m.
      const double face_y = lateral - side * (0.5 * depth + protrusion);
      const int columns = static_cast<int>((width - 1.5) / 2.6);
      for (double z = ground + 1.2; z + 1.6 < ground + height; z += 3.2) {
        for (int c = 0; c < columns; ++c) {
          const double x = -0.5 * (columns - 1) * 2.6 + c * 2.6;
          builder.AddBox(Local(frame, x, face_y, z + 0.75), {0.6, 0.05 + protrusion, 0.75}, frame.heading,
                         Material::kGlass);
        }
      }
    }
    s += width + (Chance(rng, 0.35) ? Uniform(rng, 3.0, 10.0) : Uniform(rng, 0.5, 1.5));
  }
}

void AddParkedCars(const ScenePath& path, double side, std::mt19937_64& rng, Placer& placer,
                   MeshBuilder& builder) {
  for (double s = Uniform(rng, 2.0, 8.0); s < path.length(); s += Uniform(rng, 5.5, 8.0)) {
    if (!Chance(rng, 0.55)) continue;
    const double length = Uniform(rng, 4.0, 4.8);
    const ScenePath::Sample frame = path.At(s);
    const double ground = frame.position.z() - path.body_height();
    const Eigen::Vector3d center = Local(frame, 0.0, side * 4.5, ground);
    if (!placer.TryPlace(RectFootprint(center.head<2>(), 0.5 * length, 0.9, frame.heading))) continue;
    const double yaw = frame.heading + (Chance(rng, 0.8) ? 0.0 : std::numbers::pi);
    const double c = std::cos(yaw), sn = std::sin(yaw);
    auto at = [&](double x, double y, double z) {
      return Eigen::Vector3d(center.x() + c * x - sn * y, center.y() + sn * x + c * y, ground + z);
    };
    builder.AddBox(at(0.0, 0.0, 0.7), {0.5 * length, 0.9, 0.38}, yaw, Material::kCarPaint);          // body
    builder.AddBox(at(-0.1 * length, 0.0, 1.3), {0.28 * length, 0.8, 0.25}, yaw, Material::kGlass);  // cabin
    for (const double x : {-0.32 * length, 0.32 * length}) {
      for (const double y : {-0.75, 0.75})
        builder.AddBox(at(x, y, 0.33), {0.33, 0.12, 0.33}, yaw, Material::kAsphalt);
    }
  }
}

void AddPolesAndTrees(const ScenePath& path, double side, std::mt19937_64& rng, Placer& placer,
                      MeshBuilder& builder) {
  for (double s = Uniform(rng, 0.0, 15.0); s < path.length(); s += Uniform(rng, 15.0, 25.0)) {
    // Street light: a 10 cm metal pole on the sidewalk with an arm reaching 1.5 m over the road.
    const ScenePath::Sample frame = path.At(s);
    const double ground = frame.position.z() - path.body_height() + kCurbHeight;
    const double height = Uniform(rng, 5.0, 8.0);
    const Eigen::Vector3d base = Local(frame, 0.0, side * 6.0, ground);
    const Eigen::Vector3d arm = Local(frame, 0.0, side * 5.25, ground + height - 0.1);
    // The arm only needs the clearance (it is above parked cars); the pole must not hit other objects.
    if (!placer.TryPlace(RectFootprint(Local(frame, 0.0, side * 5.3, 0.0).head<2>(), 0.2, 0.9, frame.heading),
                         false) ||
        !placer.TryPlace(CircleFootprint(base.head<2>(), 0.1))) {
      continue;
    }
    builder.AddCylinder(base, 0.1, height, 8, Material::kMetal);
    builder.AddBox(arm, {0.1, 0.75, 0.05}, frame.heading, Material::kMetal);
  }
  for (double s = Uniform(rng, 0.0, 10.0); s < path.length(); s += Uniform(rng, 8.0, 20.0)) {
    if (!Chance(rng, 0.6)) continue;
    const ScenePath::Sample frame = path.At(s);
    const double ground = frame.position.z() - path.body_height() + kCurbHeight;
    const double trunk_radius = Uniform(rng, 0.12, 0.22), trunk_height = Uniform(rng, 2.5, 4.0);
    const double crown = Uniform(rng, 1.0, 1.4), crown_z = Uniform(rng, 1.4, 2.4);
    const Eigen::Vector3d base = Local(frame, 0.0, side * 7.5, ground - 0.1);
    if (!placer.TryPlace(CircleFootprint(base.head<2>(), 1.25 * crown), false)) continue;
    if (!placer.TryPlace(CircleFootprint(base.head<2>(), trunk_radius))) continue;
    builder.AddCylinder(base, trunk_radius, trunk_height + 0.1, 7, Material::kBark);
    builder.AddBlob(base + Eigen::Vector3d(0, 0, trunk_height + 0.6 * crown_z), {crown, crown, crown_z}, 2,
                    0.2, rng(), Material::kFoliage);
  }
}

}  // namespace

void BuildUrban(const ScenePath& track, std::uint64_t seed, TriangleMesh& mesh) {
  const ScenePath path = track.Extended(kExtension);
  std::mt19937_64 rng(seed);
  MeshBuilder builder(mesh);
  AddRoad(path, builder);
  // Ground beyond the sidewalks; under the road band it is lowered 5 cm so that it stays hidden.
  AddGround(
      path, 60.0, 80.0, 4.0, kSidewalkOuter - 0.5,
      [](double, double, double d) { return d < kSidewalkOuter ? -0.05 : 0.0; },
      [](double, double, double, double) { return Material::kConcrete; }, mesh);
  Placer placer(path, 3.0);
  for (const double side : {1.0, -1.0}) AddBuildings(path, side, rng, placer, builder);
  for (const double side : {1.0, -1.0}) AddParkedCars(path, side, rng, placer, builder);
  for (const double side : {1.0, -1.0}) AddPolesAndTrees(path, side, rng, placer, builder);
}

}  // namespace uf::sim
