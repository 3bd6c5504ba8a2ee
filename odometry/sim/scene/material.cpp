#include <array>
#include <cassert>

#include "odometry/sim/scene/scene.h"

namespace uf::sim {

namespace {

const std::array<MaterialAppearance, static_cast<std::size_t>(Material::kCount)> kAppearances = {{
    {"asphalt", {0.10f, 0.10f, 0.11f}, 0.08f},
    {"road_marking", {0.85f, 0.85f, 0.80f}, 0.60f},
    {"sidewalk", {0.45f, 0.43f, 0.40f}, 0.25f},
    {"concrete", {0.55f, 0.54f, 0.50f}, 0.30f},
    {"brick", {0.50f, 0.22f, 0.15f}, 0.35f},
    {"plaster", {0.80f, 0.75f, 0.62f}, 0.45f},
    {"glass", {0.20f, 0.30f, 0.35f}, 0.05f},
    {"car_paint", {0.60f, 0.08f, 0.06f}, 0.50f},
    {"metal", {0.55f, 0.57f, 0.60f}, 0.70f},
    {"bark", {0.30f, 0.20f, 0.12f}, 0.20f},
    {"foliage", {0.12f, 0.35f, 0.10f}, 0.40f},
    {"grass", {0.20f, 0.45f, 0.15f}, 0.35f},
    {"soil", {0.35f, 0.25f, 0.15f}, 0.20f},
    {"rock", {0.45f, 0.44f, 0.42f}, 0.30f},
    {"shelf_steel", {0.15f, 0.25f, 0.60f}, 0.65f},
    {"cardboard", {0.60f, 0.45f, 0.28f}, 0.35f},
    {"tunnel_lining", {0.65f, 0.65f, 0.62f}, 0.40f},
}};

}  // namespace

const MaterialAppearance& AppearanceOf(Material material) {
  const auto index = static_cast<std::size_t>(material);
  assert(index < kAppearances.size());
  return kAppearances[index];
}

}  // namespace uf::sim
