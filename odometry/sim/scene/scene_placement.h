// Helpers shared by the scene generators: seeds (splitmix64), uniform draws, object footprints (convex xy
// polygons) and a Placer that admits an object only if its footprint keeps a clearance from the whole track
// (any path sample, so self-crossing or turning paths stay free) and does not overlap objects placed before.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <string_view>
#include <vector>

#include "odometry/sim/scene/scene_path.h"

namespace uf::sim {

// splitmix64 (Steele, Lea, Flood 2014): a bijective 64-bit mixer for deriving sub-seeds.
std::uint64_t SplitMix64(std::uint64_t x);
// A sub-seed for a named stream: splitmix64 of the seed xor an FNV-1a hash of the name.
std::uint64_t SubSeed(std::uint64_t seed, std::string_view stream);

// Uniform in [lo, hi).
double Uniform(std::mt19937_64& rng, double lo, double hi);
// True with probability p.
bool Chance(std::mt19937_64& rng, double p);

// Counter-clockwise rectangle of half sizes (hx, hy) around center, rotated by yaw (rad).
std::vector<Eigen::Vector2d> RectFootprint(const Eigen::Vector2d& center, double hx, double hy, double yaw);
// Counter-clockwise regular octagon circumscribing the circle (center, radius).
std::vector<Eigen::Vector2d> CircleFootprint(const Eigen::Vector2d& center, double radius);
// Whether two convex counter-clockwise polygons overlap (separating axis theorem; touching counts).
bool ConvexOverlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b);

class Placer {
 public:
  Placer(const ScenePath& path, double clearance) : path_(path), clearance_(clearance) {}

  // Admits (and remembers) the footprint if it keeps the clearance from the track and, when
  // check_overlap, overlaps no footprint admitted before with check_overlap.
  bool TryPlace(const std::vector<Eigen::Vector2d>& footprint, bool check_overlap = true);

 private:
  const ScenePath& path_;
  double clearance_;
  std::vector<std::vector<Eigen::Vector2d>> placed_;
};

}  // namespace uf::sim
