// A road tunnel: a horseshoe cross-section swept along the track (open ends 60 m beyond it). In (left, up)
// coordinates of the track frame, with up measured from the road surface: the road is the chord u = 0 of a
// circle of radius R = 5.5 m centred at (0, c = 1.5 m), i.e. |l| <= sqrt(R^2 - c^2) = 5.29 m; the smooth
// lining is the arc above it. Asphalt road with lane markings, lamps under the crown every 25 m.
#include <cmath>
#include <numbers>
#include <vector>

#include "odometry/sim/scene/mesh_builder.h"
#include "odometry/sim/scene/scene_generators.h"

namespace uf::sim {

namespace {

constexpr double kRadius = 5.5;
constexpr double kCenterHeight = 1.5;
constexpr int kArcSegments = 28;

}  // namespace

void BuildTunnel(const ScenePath& track, std::uint64_t /*seed*/, TriangleMesh& mesh) {
  const ScenePath path = track.Extended(60.0);
  MeshBuilder builder(mesh);
  // Arc points (R cos(phi), c + R sin(phi)) with phi from pi + alpha (right road edge) down to -alpha (left
  // road edge) through pi / 2 (crown), alpha = asin(c / R): walked right -> over the top -> left so that the
  // lining faces inwards; the road chord (left -> right) closes the profile and faces up.
  const double alpha = std::asin(kCenterHeight / kRadius);
  std::vector<Eigen::Vector2d> profile = {{kRadius * std::cos(alpha), 0.0}};
  std::vector<Material> materials = {Material::kAsphalt};
  for (int k = 0; k < kArcSegments; ++k) {
    const double phi = std::numbers::pi + alpha - k * (std::numbers::pi + 2.0 * alpha) / kArcSegments;
    profile.emplace_back(kRadius * std::cos(phi), k == 0 ? 0.0 : kCenterHeight + kRadius * std::sin(phi));
    materials.push_back(Material::kTunnelLining);
  }
  const std::vector<Eigen::Vector3d> ground = path.GroundPolyline(0.0, path.length());
  builder.AddSweptProfile(ground, profile, materials, true);

  // Markings 1 cm above the road: solid edge lines at +-3.5 m, dashed centre line (4 m every 12 m).
  const std::vector<Eigen::Vector3d> paint = path.GroundPolyline(0.0, path.length(), 0.01);
  for (const double y : {3.5, -3.5}) {
    builder.AddSweptProfile(paint, {{y + 0.075, 0.0}, {y - 0.075, 0.0}}, {Material::kRoadMarking});
  }
  for (double s = 0.0; s + 4.0 <= path.length(); s += 12.0) {
    builder.AddSweptProfile(path.GroundPolyline(s, s + 4.0, 0.01), {{0.075, 0.0}, {-0.075, 0.0}},
                            {Material::kRoadMarking});
  }
  // Lamps hanging just below the crown (an arc vertex at phi = pi / 2, height c + R).
  const double crown = kCenterHeight + kRadius;
  for (double s = 10.0; s < path.length(); s += 25.0) {
    builder.AddBox(path.GroundPoint(s, 0.0, crown - 0.35), {0.7, 0.2, 0.08}, path.At(s).heading,
                   Material::kMetal);
  }
}

}  // namespace uf::sim
