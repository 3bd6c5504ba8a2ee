#include "mapping/meshing.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace uf::mapping {
namespace {

// A point in the grid's local frame (map position - origin).
struct LocalPoint {
  Eigen::Vector3f position;
  Eigen::Vector3f normal;
  std::array<std::uint8_t, 3> rgb;
  bool has_color;
};

// The points bucketed by voxel: `head` holds the first point of each occupied voxel, next[i] the one after i
// in the same voxel (-1 ends the list).
class PointBuckets {
 public:
  PointBuckets(double voxel_size) : inv_voxel_(1.0 / voxel_size), head_(openvdb::Int32Grid::create(-1)) {}

  openvdb::Coord VoxelOf(const Eigen::Vector3f& p) const {
    return openvdb::Coord(static_cast<int>(std::floor(p.x() * inv_voxel_ + 0.5)),
                          static_cast<int>(std::floor(p.y() * inv_voxel_ + 0.5)),
                          static_cast<int>(std::floor(p.z() * inv_voxel_ + 0.5)));
  }
  void Add(const LocalPoint& point) {
    auto accessor = head_->getAccessor();
    const openvdb::Coord ijk = VoxelOf(point.position);
    next_.push_back(accessor.getValue(ijk));
    accessor.setValue(ijk, static_cast<std::int32_t>(points_.size()));
    points_.push_back(point);
  }
  const std::vector<LocalPoint>& points() const { return points_; }

  // The nearest point to q within `radius` (optionally only coloured ones), or -1.
  std::int32_t Nearest(const Eigen::Vector3f& q, float radius, bool require_color) const {
    const openvdb::Coord low = VoxelOf(q - Eigen::Vector3f::Constant(radius));
    const openvdb::Coord high = VoxelOf(q + Eigen::Vector3f::Constant(radius));
    auto accessor = head_->getConstAccessor();
    float best = radius * radius;
    std::int32_t found = -1;
    for (int x = low.x(); x <= high.x(); ++x)
      for (int y = low.y(); y <= high.y(); ++y)
        for (int z = low.z(); z <= high.z(); ++z)
          for (std::int32_t i = accessor.getValue(openvdb::Coord(x, y, z)); i >= 0;
               i = next_[static_cast<std::size_t>(i)]) {
            const LocalPoint& p = points_[static_cast<std::size_t>(i)];
            if (require_color && !p.has_color) continue;
            const float d2 = (p.position - q).squaredNorm();
            if (d2 <= best) best = d2, found = i;
          }
    return found;
  }

 private:
  double inv_voxel_;
  openvdb::Int32Grid::Ptr head_;
  std::vector<std::int32_t> next_;
  std::vector<LocalPoint> points_;
};

// Step 1: f(x) = n . (x - p) of the nearest point p with a normal, in the voxels within `band` of p.
openvdb::FloatGrid::Ptr SignedDistance(const PointBuckets& buckets, const MeshOptions& options) {
  const auto voxel = static_cast<float>(options.voxel_size_m);
  const int band = options.band_voxels;
  auto sdf = openvdb::FloatGrid::create(static_cast<float>(band + 1) * voxel);
  sdf->setTransform(openvdb::math::Transform::createLinearTransform(options.voxel_size_m));
  sdf->setGridClass(openvdb::GRID_LEVEL_SET);
  auto nearest = openvdb::FloatGrid::create(std::numeric_limits<float>::infinity());  // squared distance
  auto f = sdf->getAccessor();
  auto d2_best = nearest->getAccessor();
  for (const LocalPoint& p : buckets.points()) {
    if (p.normal.squaredNorm() == 0) continue;
    const openvdb::Coord centre = buckets.VoxelOf(p.position);
    for (int dx = -band; dx <= band; ++dx)
      for (int dy = -band; dy <= band; ++dy)
        for (int dz = -band; dz <= band; ++dz) {
          const openvdb::Coord ijk = centre.offsetBy(dx, dy, dz);
          const Eigen::Vector3f d = Eigen::Vector3f(ijk.x(), ijk.y(), ijk.z()) * voxel - p.position;
          const float d2 = d.squaredNorm();
          if (d2 >= d2_best.getValue(ijk)) continue;
          d2_best.setValue(ijk, d2);
          f.setValue(ijk, p.normal.dot(d));
        }
  }
  return sdf;
}

}  // namespace

Status MeshOptions::Validate() const {
  if (!(voxel_size_m > 0.0 && std::isfinite(voxel_size_m)))
    return Status::Error("mesh.voxel_size_m: must be finite and > 0, got " + std::to_string(voxel_size_m));
  if (band_voxels < 1 || band_voxels > 8)
    return Status::Error("mesh.band_voxels: must be in [1, 8], got " + std::to_string(band_voxels));
  if (!(max_vertex_distance_voxels > 0.0 && std::isfinite(max_vertex_distance_voxels)))
    return Status::Error("mesh.max_vertex_distance_voxels: must be finite and > 0, got " +
                         std::to_string(max_vertex_distance_voxels));
  if (!(color_search_voxels >= 0.0 && std::isfinite(color_search_voxels)))
    return Status::Error("mesh.color_search_voxels: must be finite and >= 0, got " +
                         std::to_string(color_search_voxels));
  if (!(adaptivity >= 0.0 && adaptivity <= 1.0))
    return Status::Error("mesh.adaptivity: must be in [0, 1], got " + std::to_string(adaptivity));
  return {};
}

Expected<ColoredMesh> MeshFromMap(const PointSource& source, const MeshOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  openvdb::initialize();
  ColoredMesh mesh;
  if (source.size() == 0) return mesh;
  // The local origin: the centre of the bounds on the grid, so voxel centres stay at ijk * voxel_size.
  const Eigen::Vector3d origin =
      (source.bounds().center() / options.voxel_size_m).array().round().matrix() * options.voxel_size_m;
  PointBuckets buckets(options.voxel_size_m);
  source.ForEachChunk([&](std::span<const MapPoint> chunk) {
    for (const MapPoint& p : chunk)
      if (p.position.allFinite())
        buckets.Add({(p.position - origin).cast<float>(), p.normal, p.rgb, p.has_color});
    return true;
  });

  // Step 2: the zero crossing of the signed distance.
  std::vector<openvdb::Vec3s> vertices;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*SignedDistance(buckets, options), vertices, triangles, quads, 0.0,
                               options.adaptivity);

  // Step 3: keep the vertices near a point (new index, or -1), with the colour and normal of step 4.
  const auto voxel = static_cast<float>(options.voxel_size_m);
  const float max_distance = static_cast<float>(options.max_vertex_distance_voxels) * voxel;
  const float color_distance = static_cast<float>(options.color_search_voxels) * voxel;
  std::vector<std::int64_t> kept(vertices.size(), -1);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3f v(vertices[i].x(), vertices[i].y(), vertices[i].z());
    const std::int32_t near = buckets.Nearest(v, max_distance, false);
    if (near < 0) continue;
    kept[i] = static_cast<std::int64_t>(mesh.vertices.size());
    mesh.vertices.push_back(origin + v.cast<double>());
    mesh.normals.push_back(buckets.points()[static_cast<std::size_t>(near)].normal);
    const std::int32_t colored = buckets.Nearest(v, color_distance, true);
    mesh.colors.push_back(colored >= 0 ? buckets.points()[static_cast<std::size_t>(colored)].rgb
                                       : std::array<std::uint8_t, 3>{128, 128, 128});
  }
  // volumeToMesh winds polygons clockwise seen from the positive (outside) side: reverse them so they are
  // counter-clockwise seen from outside. A quad (a, b, c, d) becomes triangles (a, b, c) and (a, c, d).
  const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (kept[a] < 0 || kept[b] < 0 || kept[c] < 0) return;
    mesh.triangles.push_back({static_cast<std::uint32_t>(kept[c]), static_cast<std::uint32_t>(kept[b]),
                              static_cast<std::uint32_t>(kept[a])});
  };
  for (const openvdb::Vec3I& t : triangles) add(t[0], t[1], t[2]);
  for (const openvdb::Vec4I& q : quads) {
    add(q[0], q[1], q[2]);
    add(q[0], q[2], q[3]);
  }
  return mesh;
}

}  // namespace uf::mapping
