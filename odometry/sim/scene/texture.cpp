// Procedural surface textures: SurfaceColor(material, p, n) = base colour of the material modulated by a
// deterministic pattern evaluated in the plane of the surface.
//
// Texture coordinates (u, v) are the two world axes most orthogonal to the normal n: the axis with the
// largest |n_i| is dropped. Walls (n horizontal) thus get v = z (vertical), floors get (u, v) = (x, y).
// Noise: integer-lattice hash value noise (lattice_noise.h), no std RNG.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "odometry/sim/scene/lattice_noise.h"
#include "odometry/sim/scene/scene.h"

namespace uf::sim {

namespace {

using namespace noise;  // NOLINT: Hash, ValueNoise, Fbm, ...

// A rectangular tiling with joint lines: returns 0 inside a joint of width `joint` (m) and 1 elsewhere;
// the tile index is written to (ti, tj). Rows are offset by `row_offset` (fraction of a tile, running bond).
double Tiles(double u, double v, double width, double height, double joint, double row_offset,
             std::int64_t& ti, std::int64_t& tj) {
  const double row = std::floor(v / height);
  const double shifted = u / width + row_offset * row;
  const double col = std::floor(shifted);
  ti = static_cast<std::int64_t>(col);
  tj = static_cast<std::int64_t>(row);
  const double du = (shifted - col) * width, dv = (v / height - row) * height;
  const bool in_joint = du < joint || dv < joint;
  return in_joint ? 0.0 : 1.0;
}

// Sparse dark spots of radius up to `radius` on a lattice of `cell`: returns 1 - darkness.
double Spots(double u, double v, double cell, double radius, double density, std::uint32_t salt) {
  const auto i = static_cast<std::int64_t>(std::floor(u / cell));
  const auto j = static_cast<std::int64_t>(std::floor(v / cell));
  if (CellValue(i, j, salt) > density) return 1.0;
  const double cu = (static_cast<double>(i) + 0.2 + 0.6 * CellValue(i, j, salt + 1)) * cell;
  const double cv = (static_cast<double>(j) + 0.2 + 0.6 * CellValue(i, j, salt + 2)) * cell;
  const double r = radius * (0.4 + 0.6 * CellValue(i, j, salt + 3));
  const double d2 = (u - cu) * (u - cu) + (v - cv) * (v - cv);
  return d2 < r * r ? 0.0 : 1.0;
}

// A printed shipping label on cardboard: lattice cells of 0.5 m may carry a white rectangle with black
// barcode bars. Returns {is_label, ink} where ink = 1 for black print.
void Label(double u, double v, bool& is_label, bool& ink) {
  const double cell = 0.5;
  const auto i = static_cast<std::int64_t>(std::floor(u / cell));
  const auto j = static_cast<std::int64_t>(std::floor(v / cell));
  is_label = false;
  ink = false;
  if (CellValue(i, j, 71) > 0.6) return;
  const double lu = u / cell - static_cast<double>(i), lv = v / cell - static_cast<double>(j);
  const double w = 0.3 + 0.3 * CellValue(i, j, 72), h = 0.2 + 0.3 * CellValue(i, j, 73);
  const double u0 = 0.1 + (0.8 - w) * CellValue(i, j, 74), v0 = 0.1 + (0.8 - h) * CellValue(i, j, 75);
  if (lu < u0 || lu > u0 + w || lv < v0 || lv > v0 + h) return;
  is_label = true;
  const double x = (lu - u0) / w, y = (lv - v0) / h;
  if (y > 0.15 && y < 0.55 && x > 0.08 && x < 0.92) {
    // Barcode: 24 bars of hashed width parity.
    const auto bar = static_cast<std::int64_t>(std::floor(x * 24.0));
    ink = CellValue(bar, i * 131 + j, 76) < 0.5;
  } else if (y > 0.65 && y < 0.85 && x > 0.08 && x < 0.6) {
    ink = true;  // a printed text block
  }
}

// Greyscale modulation (around 1) and an optional colour override for each material.
Eigen::Vector3f Shade(Material material, double u, double v) {
  const Eigen::Vector3f base = AppearanceOf(material).base_rgb;
  std::int64_t ti = 0, tj = 0;
  auto scaled = [&](double m) { return Eigen::Vector3f(base * static_cast<float>(m)); };
  switch (material) {
    case Material::kAsphalt: {
      // Gravel speckle (2 cm), patches (0.5-2 m), occasional repaired dark patches.
      const double speckle = ValueNoise(u, v, 0.02, 1);
      const double patch = Fbm(u, v, 2.0, 3, 2);
      double m = 0.55 + 0.9 * patch + (speckle > 0.8 ? 1.2 : speckle < 0.2 ? -0.35 : 0.0);
      m *= Spots(u, v, 1.5, 0.45, 0.25, 3) < 1.0 ? 0.5 : 1.0;
      return scaled(m);
    }
    case Material::kRoadMarking: {
      const double wear = Fbm(u, v, 0.3, 3, 5);
      return scaled(wear > 0.72 ? 0.35 : 0.95 + 0.1 * wear);
    }
    case Material::kSidewalk: {
      const double tile = Tiles(u, v, 0.4, 0.4, 0.012, 0.0, ti, tj);
      const double shade = 0.8 + 0.4 * CellValue(ti, tj, 7) + 0.3 * (ValueNoise(u, v, 0.03, 8) - 0.5);
      return scaled(tile > 0.0 ? shade : 0.35);
    }
    case Material::kConcrete: {
      // Formwork panels 1.2 m x 0.6 m with joints, tie holes, stains.
      const double joint = Tiles(u, v, 1.2, 0.6, 0.015, 0.0, ti, tj);
      const double stains = Fbm(u, v, 1.0, 4, 9);
      const double holes = Spots(u, v, 0.3, 0.025, 0.15, 10);
      const double m = (0.7 + 0.6 * stains + 0.15 * CellValue(ti, tj, 11)) * (joint > 0.0 ? 1.0 : 0.45);
      return scaled(m * (holes < 1.0 ? 0.3 : 1.0));
    }
    case Material::kBrick: {
      // Bricks 0.24 m x 0.075 m (incl. 1 cm mortar), running bond; per-brick colour variation.
      const double brick = Tiles(u, v, 0.24, 0.075, 0.01, 0.5, ti, tj);
      if (brick == 0.0) return Eigen::Vector3f(0.72f, 0.70f, 0.65f);  // mortar
      const double tone = 0.65 + 0.7 * CellValue(ti, tj, 12) + 0.25 * (ValueNoise(u, v, 0.03, 13) - 0.5);
      const double soot = 0.75 + 0.25 * Fbm(u, v, 1.5, 3, 14);
      return scaled(tone * soot);
    }
    case Material::kPlaster: {
      const double grain = ValueNoise(u, v, 0.02, 15);
      const double stains = Fbm(u, v, 0.8, 4, 16);
      double m = 0.85 + 0.15 * grain;
      if (stains > 0.62) m *= 0.55;  // dark water stains with sharp edges
      if (stains < 0.3) m *= 1.1;
      return scaled(m);
    }
    case Material::kGlass: {
      // Window panes 0.6 m x 0.9 m in dark frames; reflections as large soft noise.
      const double pane = Tiles(u, v, 0.6, 0.9, 0.05, 0.0, ti, tj);
      if (pane == 0.0) return Eigen::Vector3f(0.08f, 0.08f, 0.09f);
      const double reflection = Fbm(u, v, 1.2, 3, 17);
      return scaled(0.6 + 1.4 * reflection * reflection + 0.3 * CellValue(ti, tj, 18));
    }
    case Material::kCarPaint: {
      const double flake = ValueNoise(u, v, 0.01, 19);
      const double highlight = Fbm(u, v, 0.7, 2, 20);
      const double dirt = Spots(u, v, 0.15, 0.03, 0.2, 21);
      return scaled((0.8 + 0.2 * flake + (highlight > 0.7 ? 0.8 : 0.0)) * (dirt < 1.0 ? 0.5 : 1.0));
    }
    case Material::kMetal: {
      const double brushed = ValueNoise(u * 8.0, v, 0.2, 22);  // streaks along v
      const double rust = Fbm(u, v, 0.5, 4, 23);
      if (rust > 0.68) return Eigen::Vector3f(0.40f, 0.20f, 0.08f);
      return scaled(0.75 + 0.4 * brushed);
    }
    case Material::kBark: {
      // Vertical furrows: noise stretched along v (vertical on a trunk).
      const double furrow = ValueNoise(u, v * 0.1, 0.03, 24);
      const double knots = Spots(u, v, 0.25, 0.04, 0.3, 25);
      return scaled((furrow > 0.6 ? 1.3 : 0.6 + 0.5 * furrow) * (knots < 1.0 ? 0.4 : 1.0));
    }
    case Material::kFoliage: {
      // Leaf clusters (5-10 cm) with dark gaps and sunlit tips.
      const double leaves = Fbm(u, v, 0.12, 3, 26);
      const double m = leaves < 0.4 ? 0.35 : leaves > 0.62 ? 1.6 : 1.0;
      return scaled(m * (0.85 + 0.3 * ValueNoise(u, v, 0.8, 27)));
    }
    case Material::kGrass: {
      const double blades = ValueNoise(u, v, 0.015, 28);
      const double tufts = Fbm(u, v, 0.6, 4, 29);
      if (tufts < 0.33) return Eigen::Vector3f(0.32f, 0.24f, 0.13f) * (0.8f + 0.4f * float(blades));
      return scaled(0.6 + 0.6 * tufts + 0.4 * blades + (tufts > 0.7 ? 0.4 : 0.0));
    }
    case Material::kSoil: {
      const double clods = Fbm(u, v, 0.3, 4, 30);
      const double pebbles = Spots(u, v, 0.08, 0.02, 0.35, 31);
      return scaled((0.6 + 0.8 * clods) * (pebbles < 1.0 ? 1.9 : 1.0));
    }
    case Material::kRock: {
      const double grain = ValueNoise(u, v, 0.02, 32);
      const double veins = Fbm(u, v, 0.5, 4, 33);
      const double lichen = Fbm(u, v, 0.25, 3, 34);
      if (lichen > 0.68) return Eigen::Vector3f(0.55f, 0.58f, 0.35f);
      return scaled((0.7 + 0.6 * veins + 0.2 * grain) * (std::abs(veins - 0.5) < 0.02 ? 0.4 : 1.0));
    }
    case Material::kShelfSteel: {
      // Punched slots every 5 cm along v (the long axis of uprights and beams), paint scratches.
      const double slot = Tiles(u * 4.0, v, 0.1, 0.05, 0.03, 0.0, ti, tj);
      const double scratches = ValueNoise(u * 0.2, v * 3.0, 0.08, 35);
      return scaled((slot == 0.0 ? 0.3 : 1.0) * (scratches > 0.85 ? 1.6 : 1.0));
    }
    case Material::kCardboard: {
      bool is_label = false, ink = false;
      Label(u, v, is_label, ink);
      if (is_label) return ink ? Eigen::Vector3f(0.04f, 0.04f, 0.04f) : Eigen::Vector3f(0.92f, 0.92f, 0.9f);
      const double tape = std::abs(std::remainder(u, 0.5)) < 0.025 ? 1.3 : 1.0;  // packing tape strips
      return scaled((0.8 + 0.3 * Fbm(u, v, 0.2, 3, 36)) * tape);
    }
    case Material::kTunnelLining: {
      // Precast panels 2.5 m x 1.5 m with dark joints, per-panel tone, vertical grime streaks.
      const double joint = Tiles(u, v, 2.5, 1.5, 0.03, 0.5, ti, tj);
      const double tone = 0.8 + 0.3 * CellValue(ti, tj, 37);
      const double grime = ValueNoise(u, v * 0.15, 0.15, 38);
      const double bolts = Spots(u, v, 0.5, 0.03, 0.25, 39);
      return scaled((joint > 0.0 ? tone * (0.75 + 0.45 * grime) : 0.25) * (bolts < 1.0 ? 0.35 : 1.0));
    }
    case Material::kCount:
      break;
  }
  return base;
}

}  // namespace

Eigen::Vector3f SurfaceColor(Material material, const Eigen::Vector3d& p, const Eigen::Vector3f& n) {
  // Drop the world axis most aligned with the normal; the remaining two span (approximately) the surface.
  const Eigen::Vector3f a = n.cwiseAbs();
  double u = 0.0, v = 0.0;
  if (a.z() >= a.x() && a.z() >= a.y()) {
    u = p.x(), v = p.y();  // floor / ceiling
  } else if (a.x() >= a.y()) {
    u = p.y(), v = p.z();  // wall facing +-x
  } else {
    u = p.x(), v = p.z();  // wall facing +-y
  }
  const Eigen::Vector3f rgb = Shade(material, u, v);
  return rgb.cwiseMax(0.0f).cwiseMin(1.0f);
}

}  // namespace uf::sim
