#include "odometry/sim/scene/scene_placement.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace uf::sim {

std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

std::uint64_t SubSeed(std::uint64_t seed, std::string_view stream) {
  std::uint64_t h = 0xCBF29CE484222325ULL;  // FNV-1a offset basis
  for (const char c : stream) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001B3ULL;  // FNV prime
  }
  return SplitMix64(seed ^ h);
}

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  // 53 random bits -> [0, 1), independent of the library's uniform_real_distribution.
  const double u = static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
  return lo + (hi - lo) * u;
}

bool Chance(std::mt19937_64& rng, double p) { return Uniform(rng, 0.0, 1.0) < p; }

std::vector<Eigen::Vector2d> RectFootprint(const Eigen::Vector2d& center, double hx, double hy, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<Eigen::Vector2d> out;
  for (const auto& [x, y] :
       {std::pair{-hx, -hy}, std::pair{hx, -hy}, std::pair{hx, hy}, std::pair{-hx, hy}}) {
    out.push_back(center + Eigen::Vector2d(c * x - s * y, s * x + c * y));
  }
  return out;
}

std::vector<Eigen::Vector2d> CircleFootprint(const Eigen::Vector2d& center, double radius) {
  // An octagon's vertices at radius r / cos(pi / 8) put its edges at distance r from the centre.
  const double r = radius / std::cos(std::numbers::pi / 8.0);
  std::vector<Eigen::Vector2d> out;
  for (int k = 0; k < 8; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 8.0;
    out.push_back(center + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return out;
}

bool ConvexOverlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b) {
  // Separating axis theorem: convex polygons are disjoint iff some edge normal separates their projections.
  for (const auto* poly : {&a, &b}) {
    for (std::size_t i = 0; i < poly->size(); ++i) {
      const Eigen::Vector2d e = (*poly)[(i + 1) % poly->size()] - (*poly)[i];
      const Eigen::Vector2d axis(-e.y(), e.x());
      double a_min = std::numeric_limits<double>::infinity(), a_max = -a_min;
      double b_min = a_min, b_max = -a_min;
      for (const auto& v : a) {
        a_min = std::min(a_min, axis.dot(v));
        a_max = std::max(a_max, axis.dot(v));
      }
      for (const auto& v : b) {
        b_min = std::min(b_min, axis.dot(v));
        b_max = std::max(b_max, axis.dot(v));
      }
      if (a_max < b_min || b_max < a_min) return false;
    }
  }
  return true;
}

bool Placer::TryPlace(const std::vector<Eigen::Vector2d>& footprint, bool check_overlap) {
  if (!path_.PolygonClear(footprint, clearance_)) return false;
  if (check_overlap) {
    for (const auto& other : placed_) {
      if (ConvexOverlap(footprint, other)) return false;
    }
    placed_.push_back(footprint);
  }
  return true;
}

}  // namespace uf::sim
