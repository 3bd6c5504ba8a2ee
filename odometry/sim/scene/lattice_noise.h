// Integer-lattice hash value noise for procedural textures and terrain: deterministic, pure functions of
// their arguments (no std RNG), identical on every platform.
//
// value(i, j) = Hash(i, j, salt) / 2^32 in [0, 1) at integer lattice points, interpolated inside a cell with
// the quintic fade f(t) = 6t^5 - 15t^4 + 10t^3 (C2), and summed over octaves for fractional Brownian motion.
#pragma once

#include <cmath>
#include <cstdint>

namespace uf::sim::noise {

// A 32-bit integer hash of a lattice point and a salt (murmur3-like finalizer on a mixed key).
inline std::uint32_t Hash(std::int64_t i, std::int64_t j, std::uint32_t salt) {
  std::uint64_t h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL;
  h ^= static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL + 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(salt) * 0xD6E8FEB86659FD93ULL;
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDULL;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ULL;
  h ^= h >> 33;
  return static_cast<std::uint32_t>(h);
}

// Hash of a lattice cell mapped to [0, 1).
inline double CellValue(std::int64_t i, std::int64_t j, std::uint32_t salt) {
  return static_cast<double>(Hash(i, j, salt)) * (1.0 / 4294967296.0);
}

inline double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// Value noise in [0, 1) with lattice spacing `cell` (m).
inline double ValueNoise(double u, double v, double cell, std::uint32_t salt) {
  const double x = u / cell, y = v / cell;
  const double fx = std::floor(x), fy = std::floor(y);
  const auto i = static_cast<std::int64_t>(fx), j = static_cast<std::int64_t>(fy);
  const double tx = Fade(x - fx), ty = Fade(y - fy);
  const double a = CellValue(i, j, salt), b = CellValue(i + 1, j, salt);
  const double c = CellValue(i, j + 1, salt), d = CellValue(i + 1, j + 1, salt);
  return (a + (b - a) * tx) * (1.0 - ty) + (c + (d - c) * tx) * ty;
}

// Fractional Brownian motion: octaves of value noise, each half the cell size and half the weight,
// normalised to [0, 1).
inline double Fbm(double u, double v, double cell, int octaves, std::uint32_t salt) {
  double sum = 0.0, weight = 1.0, total = 0.0;
  for (int k = 0; k < octaves; ++k) {
    sum += weight * ValueNoise(u, v, cell, salt + static_cast<std::uint32_t>(k) * 101u);
    total += weight;
    weight *= 0.5;
    cell *= 0.5;
  }
  return sum / total;
}

}  // namespace uf::sim::noise
