#include "splat/seeding.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace uf::splat {

Status SeedOptions::Validate() const {
  std::ostringstream message;
  if (sh_degree < 0 || sh_degree > kMaxShDegree)
    message << "seed.sh_degree: must be in [0, 3], got " << sh_degree;
  else if (neighbours < 1 || neighbours > 32)
    message << "seed.neighbours: must be in [1, 32], got " << neighbours;
  else if (!(search_radius_m > 0 && std::isfinite(search_radius_m)))
    message << "seed.search_radius_m: must be positive, got " << search_radius_m;
  else if (!(flatness > 0 && flatness <= 1))
    message << "seed.flatness: must be in (0, 1], got " << flatness;
  else if (!(initial_opacity > 0 && initial_opacity < 1))
    message << "seed.initial_opacity: must be in (0, 1), got " << initial_opacity;
  else if (max_gaussians < 1)
    message << "seed.max_gaussians: must be at least 1, got " << max_gaussians;
  else
    return Status();
  return Status::Error(message.str());
}

namespace {

// Points hashed into cubic cells of the search radius, so the k nearest within the radius lie in the 27
// cells around a point's own.
class NeighbourGrid {
 public:
  NeighbourGrid(const std::vector<Eigen::Vector3f>& points, double cell) : points_(points), cell_(cell) {
    for (std::size_t i = 0; i < points.size(); ++i)
      cells_[Key(Cell(points[i]))].push_back(static_cast<std::uint32_t>(i));
  }

  // Mean squared distance to the k nearest other points within the radius (cell); -1 when there is none.
  double MeanSquaredDistance(std::size_t index, int k) const {
    const Eigen::Vector3f& p = points_[index];
    const Eigen::Vector3i c = Cell(p);
    std::vector<float> nearest;  // the k smallest squared distances, ascending
    const float radius2 = static_cast<float>(cell_ * cell_);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (std::uint32_t j : it->second) {
            if (j == index) continue;
            const float d2 = (points_[j] - p).squaredNorm();
            if (d2 > radius2 || (static_cast<int>(nearest.size()) == k && d2 >= nearest.back())) continue;
            nearest.insert(std::upper_bound(nearest.begin(), nearest.end(), d2), d2);
            if (static_cast<int>(nearest.size()) > k) nearest.pop_back();
          }
        }
    if (nearest.empty()) return -1;
    double sum = 0;
    for (float d2 : nearest) sum += d2;
    return sum / nearest.size();
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3f& p) const {
    return (p.cast<double>() / cell_).array().floor().cast<int>();
  }
  static std::uint64_t Key(const Eigen::Vector3i& c) {
    // 21 bits per axis (+-1e6 cells), enough for any map this stage sees.
    const auto bits = [](int v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF; };
    return bits(c.x()) | bits(c.y()) << 21 | bits(c.z()) << 42;
  }

  const std::vector<Eigen::Vector3f>& points_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace

Expected<SeedResult> SeedGaussians(const mapping::PointSource& map, const SeedOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  SeedResult result;
  result.map_points = map.size();
  std::size_t coloured = 0;
  if (options.seen_points_only)
    map.ForEachChunk([&](std::span<const mapping::MapPoint> chunk) {
      for (const mapping::MapPoint& p : chunk) coloured += p.has_color;
      return true;
    });
  const bool skip_unseen = coloured > 0;
  if (skip_unseen) result.unseen_left_out = map.size() - coloured;
  const std::size_t eligible = skip_unseen ? coloured : map.size();
  result.thinning = std::max<std::size_t>(1, (eligible + options.max_gaussians - 1) / options.max_gaussians);
  // Gather the seeded points (every thinning-th of those left in) with what the Gaussians need.
  std::vector<Eigen::Vector3f> positions, normals, colours;
  std::size_t index = 0;
  map.ForEachChunk([&](std::span<const mapping::MapPoint> chunk) {
    for (const mapping::MapPoint& p : chunk) {
      if (skip_unseen && !p.has_color) continue;
      if (index++ % result.thinning != 0 || !p.position.allFinite()) continue;
      positions.push_back(p.position.cast<float>());
      normals.push_back(p.normal.allFinite() ? p.normal : Eigen::Vector3f::Zero());
      if (!p.has_color) ++result.uncoloured;
      colours.push_back(p.has_color ? Eigen::Vector3f(Eigen::Vector3f(p.rgb[0], p.rgb[1], p.rgb[2]) / 255.0f)
                                    : Eigen::Vector3f::Constant(0.5f));
    }
    return true;
  });

  const NeighbourGrid grid(positions, options.search_radius_m);
  GaussianModel& model = result.model;
  model.sh_degree = options.sh_degree;
  const float opacity_logit =
      static_cast<float>(std::log(options.initial_opacity / (1 - options.initial_opacity)));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const double d2 = grid.MeanSquaredDistance(i, options.neighbours);
    if (d2 < 0) ++result.isolated;
    const float s = static_cast<float>(d2 >= 0 ? std::max(std::sqrt(d2), 1e-4) : options.search_radius_m / 2);
    Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
    Eigen::Vector3f scale = Eigen::Vector3f::Constant(s);
    if (normals[i].norm() > 0.5f) {
      rotation = Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), normals[i].normalized());
      scale.z() = static_cast<float>(options.flatness) * s;
    } else {
      ++result.without_normal;
    }
    model.AddConstantColor(positions[i], scale.array().log(), rotation, opacity_logit, colours[i]);
  }
  return result;
}

void AddBackgroundSphere(GaussianModel& model, const Eigen::Vector3d& centre, double radius, int count,
                         double opacity) {
  assert(radius > 0 && count > 0 && opacity > 0 && opacity < 1);
  const double spacing = radius * std::sqrt(4.0 * M_PI / count);
  const float tangent = static_cast<float>(std::log(0.5 * spacing));
  const Eigen::Vector3f log_scale(tangent, tangent, tangent - std::log(10.0f));
  const float logit = static_cast<float>(std::log(opacity / (1.0 - opacity)));
  // Fibonacci lattice: z evenly spaced in (-1, 1), longitude advancing by the golden angle.
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count, r = std::sqrt(1.0 - z * z), longitude = golden_angle * i;
    const Eigen::Vector3d direction(r * std::cos(longitude), r * std::sin(longitude), z);
    const Eigen::Quaternionf rotation =
        Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), direction.cast<float>());
    model.AddConstantColor((centre + radius * direction).cast<float>(), log_scale, rotation, logit,
                           Eigen::Vector3f::Constant(0.5f));
  }
}

}  // namespace uf::splat
