#include "mapping/map_file.h"

#include <openvdb/io/Stream.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "mapping/global_map_impl.h"
#include "odometry/io/atomic_file.h"

namespace uf::mapping {
namespace {

constexpr int kFormatVersion = 2;  // 2: georef_T_enu_map added

// The grids of the file, by name (see map_file.h).
struct MapGrids {
  openvdb::Vec3SGrid::Ptr offset, view_sum, color_mean;
  openvdb::Int32Grid::Ptr count, color_count;
  openvdb::Int64Grid::Ptr last_stamp;
  openvdb::FloatGrid::Ptr intensity, color_m2;
};

template <typename GridT>
typename GridT::Ptr MakeGrid(const char* name, double voxel_size) {
  typename GridT::Ptr grid = GridT::create();
  grid->setName(name);
  grid->setTransform(VoxelTransform(voxel_size));
  return grid;
}

// Exception texts of a corrupt file can carry the garbage bytes they read: keep them short and printable.
std::string Printable(const char* text) {
  std::string out;
  for (const char* c = text; *c && out.size() < 160; ++c)
    if (std::isprint(static_cast<unsigned char>(*c)) && !(*c == ' ' && !out.empty() && out.back() == ' '))
      out += *c;
  return out;
}

void WriteMetadata(const GlobalMap::Impl& map, const std::optional<MapGeoreference>& georef,
                   openvdb::MetaMap& meta) {
  const GlobalMapConfig& c = map.config;
  meta.insertMeta("ultrafusion_map_format", openvdb::Int32Metadata(kFormatVersion));
  meta.insertMeta("voxel_size_m", openvdb::DoubleMetadata(c.voxel_size_m));
  meta.insertMeta("voxel_count", openvdb::Int64Metadata(static_cast<std::int64_t>(map.voxels.size())));
  meta.insertMeta("max_voxels", openvdb::Int64Metadata(static_cast<std::int64_t>(c.max_voxels)));
  meta.insertMeta("min_observations", openvdb::Int32Metadata(c.min_observations));
  meta.insertMeta("min_neighbors_if_unconfirmed", openvdb::Int32Metadata(c.min_neighbors_if_unconfirmed));
  meta.insertMeta("color_min_samples", openvdb::Int32Metadata(c.color_min_samples));
  meta.insertMeta("color_outlier_sigma", openvdb::DoubleMetadata(c.color_outlier_sigma));
  meta.insertMeta("color_sigma_floor", openvdb::DoubleMetadata(c.color_sigma_floor));
  meta.insertMeta("normal_radius_voxels", openvdb::Int32Metadata(c.normal_radius_voxels));
  const GlobalMapStats& s = map.stats;
  meta.insertMeta("points_inserted", openvdb::Int64Metadata(static_cast<std::int64_t>(s.points_inserted)));
  meta.insertMeta("points_skipped_invalid",
                  openvdb::Int64Metadata(static_cast<std::int64_t>(s.points_skipped_invalid)));
  meta.insertMeta("colors_rejected", openvdb::Int64Metadata(static_cast<std::int64_t>(s.colors_rejected)));
  meta.insertMeta("voxels_evicted", openvdb::Int64Metadata(static_cast<std::int64_t>(s.voxels_evicted)));
  const Eigen::Vector3d& o = map.latest_origin;
  meta.insertMeta("latest_sensor_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(o.x(), o.y(), o.z())));
  meta.insertMeta("has_georef", openvdb::BoolMetadata(georef.has_value()));
  const MapGeoreference g = georef.value_or(MapGeoreference{});
  meta.insertMeta("georef_latitude_deg", openvdb::DoubleMetadata(g.latitude_deg));
  meta.insertMeta("georef_longitude_deg", openvdb::DoubleMetadata(g.longitude_deg));
  meta.insertMeta("georef_height_m", openvdb::DoubleMetadata(g.height_m));
  const Eigen::Vector3d& t = g.T_enu_map.translation();
  const Eigen::Quaterniond q = g.T_enu_map.so3().quaternion();
  meta.insertMeta("georef_T_enu_map_translation",
                  openvdb::Vec3DMetadata(openvdb::Vec3d(t.x(), t.y(), t.z())));
  meta.insertMeta("georef_T_enu_map_quaternion",
                  openvdb::Vec4DMetadata(openvdb::Vec4d(q.x(), q.y(), q.z(), q.w())));
}

// Reads metadata `name` of type MetaT into `out`; false when it is missing or of another type.
template <typename MetaT, typename T>
bool Read(const openvdb::MetaMap& meta, const char* name, T& out) {
  const auto value = meta.getMetadata<MetaT>(name);
  if (!value) return false;
  out = static_cast<T>(value->value());
  return true;
}

// The config, statistics and georeference from the metadata, or the name of the first missing entry.
std::string ReadMetadata(const openvdb::MetaMap& meta, GlobalMapConfig& c, GlobalMapStats& s,
                         Eigen::Vector3d& origin, std::optional<MapGeoreference>& georef,
                         std::int64_t& voxel_count) {
  int format = 0;
  if (!Read<openvdb::Int32Metadata>(meta, "ultrafusion_map_format", format)) return "ultrafusion_map_format";
  if (format != kFormatVersion) return "ultrafusion_map_format (version " + std::to_string(format) + ")";
  if (!Read<openvdb::DoubleMetadata>(meta, "voxel_size_m", c.voxel_size_m)) return "voxel_size_m";
  if (!Read<openvdb::Int64Metadata>(meta, "voxel_count", voxel_count)) return "voxel_count";
  if (!Read<openvdb::Int64Metadata>(meta, "max_voxels", c.max_voxels)) return "max_voxels";
  if (!Read<openvdb::Int32Metadata>(meta, "min_observations", c.min_observations)) return "min_observations";
  if (!Read<openvdb::Int32Metadata>(meta, "min_neighbors_if_unconfirmed", c.min_neighbors_if_unconfirmed))
    return "min_neighbors_if_unconfirmed";
  if (!Read<openvdb::Int32Metadata>(meta, "color_min_samples", c.color_min_samples))
    return "color_min_samples";
  if (!Read<openvdb::DoubleMetadata>(meta, "color_outlier_sigma", c.color_outlier_sigma))
    return "color_outlier_sigma";
  if (!Read<openvdb::DoubleMetadata>(meta, "color_sigma_floor", c.color_sigma_floor))
    return "color_sigma_floor";
  if (!Read<openvdb::Int32Metadata>(meta, "normal_radius_voxels", c.normal_radius_voxels))
    return "normal_radius_voxels";
  if (!Read<openvdb::Int64Metadata>(meta, "points_inserted", s.points_inserted)) return "points_inserted";
  if (!Read<openvdb::Int64Metadata>(meta, "points_skipped_invalid", s.points_skipped_invalid))
    return "points_skipped_invalid";
  if (!Read<openvdb::Int64Metadata>(meta, "colors_rejected", s.colors_rejected)) return "colors_rejected";
  if (!Read<openvdb::Int64Metadata>(meta, "voxels_evicted", s.voxels_evicted)) return "voxels_evicted";
  openvdb::Vec3d o;
  if (!Read<openvdb::Vec3DMetadata>(meta, "latest_sensor_origin", o)) return "latest_sensor_origin";
  origin = Eigen::Vector3d(o.x(), o.y(), o.z());
  bool has_georef = false;
  MapGeoreference g;
  if (!Read<openvdb::BoolMetadata>(meta, "has_georef", has_georef)) return "has_georef";
  if (!Read<openvdb::DoubleMetadata>(meta, "georef_latitude_deg", g.latitude_deg))
    return "georef_latitude_deg";
  if (!Read<openvdb::DoubleMetadata>(meta, "georef_longitude_deg", g.longitude_deg))
    return "georef_longitude_deg";
  if (!Read<openvdb::DoubleMetadata>(meta, "georef_height_m", g.height_m)) return "georef_height_m";
  openvdb::Vec3d t;
  openvdb::Vec4d q;
  if (!Read<openvdb::Vec3DMetadata>(meta, "georef_T_enu_map_translation", t))
    return "georef_T_enu_map_translation";
  if (!Read<openvdb::Vec4DMetadata>(meta, "georef_T_enu_map_quaternion", q))
    return "georef_T_enu_map_quaternion";
  const Eigen::Quaterniond rotation(q.w(), q.x(), q.y(), q.z());
  if (!std::isfinite(rotation.norm()) || std::abs(rotation.norm() - 1.0) > 1e-6 ||
      !Eigen::Vector3d(t.x(), t.y(), t.z()).allFinite())
    return "georef_T_enu_map (not a finite rigid transform)";
  g.T_enu_map = SE3(SO3(rotation), Eigen::Vector3d(t.x(), t.y(), t.z()));
  if (has_georef) georef = g;
  return "";
}

}  // namespace

Status SaveMap(const GlobalMap& map, const std::optional<MapGeoreference>& georef,
               const std::filesystem::path& file) {
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(map);
  const double s = impl.config.voxel_size_m;
  try {
    MapGrids g{MakeGrid<openvdb::Vec3SGrid>("position_offset", s),
               MakeGrid<openvdb::Vec3SGrid>("view_direction_sum", s),
               MakeGrid<openvdb::Vec3SGrid>("color_mean", s),
               MakeGrid<openvdb::Int32Grid>("count", s),
               MakeGrid<openvdb::Int32Grid>("color_count", s),
               MakeGrid<openvdb::Int64Grid>("last_stamp", s),
               MakeGrid<openvdb::FloatGrid>("intensity", s),
               MakeGrid<openvdb::FloatGrid>("color_m2", s)};
    auto offset = g.offset->getAccessor(), view_sum = g.view_sum->getAccessor(),
         color_mean = g.color_mean->getAccessor();
    auto count = g.count->getAccessor(), color_count = g.color_count->getAccessor();
    auto last_stamp = g.last_stamp->getAccessor();
    auto intensity = g.intensity->getAccessor(), color_m2 = g.color_m2->getAccessor();
    const auto vec = [](const Eigen::Vector3f& v) { return openvdb::Vec3s(v.x(), v.y(), v.z()); };
    for (const VoxelData& v : impl.voxels) {
      offset.setValue(v.ijk, vec(v.offset_mean));
      view_sum.setValue(v.ijk, vec(v.view_sum));
      color_mean.setValue(v.ijk, vec(v.color_mean));
      count.setValue(v.ijk, static_cast<std::int32_t>(v.count));
      color_count.setValue(v.ijk, static_cast<std::int32_t>(v.color_count));
      last_stamp.setValue(v.ijk, v.last_stamp);
      intensity.setValue(v.ijk, v.intensity_mean);
      color_m2.setValue(v.ijk, v.color_m2);
    }
    openvdb::MetaMap meta;
    WriteMetadata(impl, georef, meta);
    const openvdb::GridCPtrVec grids{g.offset,      g.view_sum,   g.color_mean, g.count,
                                     g.color_count, g.last_stamp, g.intensity,  g.color_m2};
    AtomicFileWriter writer(file.string());
    if (Status status = writer.status(); !status.ok()) return status;
    openvdb::io::Stream stream(writer.stream());
    // Blosc (LZ4) when available: several times faster than zip at a similar size for these grids.
    if (openvdb::io::Archive::hasBloscCompression())
      stream.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    stream.write(grids, meta);
    return writer.Commit();
  } catch (const std::exception& error) {
    return Status::Error(file.string() + ": cannot write the map: " + Printable(error.what()));
  }
}

Expected<LoadedMap> LoadMap(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) return Status::Error(name + ": no such map file");
  openvdb::initialize();
  try {
    // Grids are read one at a time and released once copied: peak memory is the map plus one attribute
    // grid, not all eight (sparse 8^3 leaves hold far more than the voxels they keep).
    openvdb::io::File vdb(name);
    vdb.open(/*delayLoad=*/false);
    const openvdb::MetaMap::Ptr meta = vdb.getMetadata();
    GlobalMapConfig config;
    GlobalMapStats stats;
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    std::optional<MapGeoreference> georef;
    std::int64_t voxel_count = 0;
    if (std::string missing = ReadMetadata(*meta, config, stats, origin, georef, voxel_count);
        !missing.empty())
      return Status::Error(name + ": missing or bad metadata '" + missing + "' (not an ultrafusion map?)");
    if (Status s = config.Validate(); !s.ok()) return Status::Error(name + ": stored config: " + s.message());
    if (voxel_count < 0 || static_cast<std::uint64_t>(voxel_count) > config.max_voxels)
      return Status::Error(name + ": " + std::to_string(voxel_count) + " voxels: not within max_voxels");

    // An attribute grid of type GridT, checked against the metadata, or an error.
    const auto read = [&]<typename GridT>(const char* grid_name, typename GridT::Ptr& grid) -> Status {
      grid = vdb.hasGrid(grid_name) ? openvdb::gridPtrCast<GridT>(vdb.readGrid(grid_name)) : nullptr;
      if (!grid) return Status::Error(name + ": grid '" + grid_name + "' is missing or has the wrong type");
      if (grid->activeVoxelCount() != static_cast<openvdb::Index64>(voxel_count))
        return Status::Error(name + ": grid '" + grid_name + "' has " +
                             std::to_string(grid->activeVoxelCount()) + " voxels, the metadata says " +
                             std::to_string(voxel_count));
      if (std::abs(grid->voxelSize()[0] - config.voxel_size_m) > 1e-9 * config.voxel_size_m)
        return Status::Error(name + ": grid '" + grid_name + "' voxel size differs from voxel_size_m");
      return {};
    };
    auto impl = std::make_unique<GlobalMap::Impl>(config);
    impl->stats = stats;
    impl->latest_origin = origin;
    impl->voxels.reserve(static_cast<std::size_t>(voxel_count));
    auto index = impl->index->getAccessor();
    // The voxels, from the count grid.
    {
      openvdb::Int32Grid::Ptr count;
      if (Status s = read.operator()<openvdb::Int32Grid>("count", count); !s.ok()) return s;
      for (auto it = count->cbeginValueOn(); it; ++it) {
        if (*it < 1) return Status::Error(name + ": a voxel has count " + std::to_string(*it));
        VoxelData v;
        v.ijk = it.getCoord();
        v.count = static_cast<std::uint32_t>(*it);
        index.setValue(v.ijk, static_cast<std::int32_t>(impl->voxels.size()));
        impl->voxels.push_back(v);
      }
    }
    // Every other attribute, voxel by voxel; each grid has exactly the count grid's voxels (same number, and
    // each one found in the index), so every voxel gets every attribute.
    const auto fill = [&]<typename GridT, typename Set>(const char* grid_name, Set set) -> Status {
      typename GridT::Ptr grid;
      if (Status s = read.template operator()<GridT>(grid_name, grid); !s.ok()) return s;
      for (auto it = grid->cbeginValueOn(); it; ++it) {
        std::int32_t i = 0;
        if (!index.probeValue(it.getCoord(), i))
          return Status::Error(name + ": grid '" + grid_name + "' has a voxel the count grid does not");
        set(impl->voxels[static_cast<std::size_t>(i)], *it);
      }
      return {};
    };
    const auto eigen = [](const openvdb::Vec3s& v) { return Eigen::Vector3f(v.x(), v.y(), v.z()); };
    using Vec3Grid = openvdb::Vec3SGrid;
    Status s = fill.operator()<Vec3Grid>(
        "position_offset", [&](VoxelData& v, const openvdb::Vec3s& x) { v.offset_mean = eigen(x); });
    if (s.ok())
      s = fill.operator()<Vec3Grid>("view_direction_sum",
                                    [&](VoxelData& v, const openvdb::Vec3s& x) { v.view_sum = eigen(x); });
    if (s.ok())
      s = fill.operator()<Vec3Grid>("color_mean",
                                    [&](VoxelData& v, const openvdb::Vec3s& x) { v.color_mean = eigen(x); });
    if (s.ok())
      s = fill.operator()<openvdb::Int32Grid>("color_count", [&](VoxelData& v, std::int32_t n) {
        v.color_count = static_cast<std::uint32_t>(std::max(n, 0));
      });
    if (s.ok())
      s = fill.operator()<openvdb::Int64Grid>("last_stamp",
                                              [&](VoxelData& v, std::int64_t t) { v.last_stamp = t; });
    if (s.ok())
      s = fill.operator()<openvdb::FloatGrid>("intensity",
                                              [&](VoxelData& v, float x) { v.intensity_mean = x; });
    if (s.ok())
      s = fill.operator()<openvdb::FloatGrid>("color_m2", [&](VoxelData& v, float x) { v.color_m2 = x; });
    if (!s.ok()) return s;
    vdb.close();
    return LoadedMap{GlobalMapAccess::Wrap(std::move(impl)), georef};
  } catch (const std::exception& e) {
    return Status::Error(name + ": not a readable map file (truncated or corrupt?): " + Printable(e.what()));
  }
}

}  // namespace uf::mapping
