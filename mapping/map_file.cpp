#include "mapping/map_file.h"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "mapping/global_map_impl.h"
#include "odometry/io/atomic_file.h"

namespace uf::mapping {
namespace {

constexpr int kFormatVersion = 3;  // 2: georef_T_enu_map; 3: attributes in map.voxels beside the index grid

// map.voxels: a header, then one fixed-size little-endian record per voxel, in index order.
constexpr char kVoxelsMagic[8] = {'U', 'F', 'M', 'A', 'P', 'V', 'O', 'X'};
constexpr std::uint32_t kVoxelsVersion = 1;
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8;  // magic, version, record size, count
// ijk 3 x int32, offset_mean, view_sum, color_mean 3 x float each, color_m2, intensity_mean float,
// count, color_count uint32, last_stamp int64.
constexpr std::size_t kRecordSize = 12 + 36 + 8 + 8 + 8;
constexpr std::size_t kChunkRecords = 65536;

template <typename T>
void Put(char*& out, T value) {
  std::memcpy(out, &value, sizeof(T));
  out += sizeof(T);
}
template <typename T>
T Get(const char*& in) {
  T value;
  std::memcpy(&value, in, sizeof(T));
  in += sizeof(T);
  return value;
}

void PutRecord(const VoxelData& v, char* out) {
  for (int i = 0; i < 3; ++i) Put<std::int32_t>(out, v.ijk[i]);
  for (const Eigen::Vector3f* f : {&v.offset_mean, &v.view_sum, &v.color_mean})
    for (int i = 0; i < 3; ++i) Put<float>(out, (*f)[i]);
  Put<float>(out, v.color_m2);
  Put<float>(out, v.intensity_mean);
  Put<std::uint32_t>(out, v.count);
  Put<std::uint32_t>(out, v.color_count);
  Put<std::int64_t>(out, v.last_stamp);
}

VoxelData GetRecord(const char* in) {
  VoxelData v;
  for (int i = 0; i < 3; ++i) v.ijk[i] = Get<std::int32_t>(in);
  for (Eigen::Vector3f* f : {&v.offset_mean, &v.view_sum, &v.color_mean})
    for (int i = 0; i < 3; ++i) (*f)[i] = Get<float>(in);
  v.color_m2 = Get<float>(in);
  v.intensity_mean = Get<float>(in);
  v.count = Get<std::uint32_t>(in);
  v.color_count = Get<std::uint32_t>(in);
  v.last_stamp = Get<std::int64_t>(in);
  return v;
}

Status WriteVoxels(const std::vector<VoxelData>& voxels, const std::filesystem::path& file) {
  AtomicFileWriter writer(file.string());
  if (Status status = writer.status(); !status.ok()) return status;
  std::vector<char> buffer(kHeaderSize);
  char* out = buffer.data();
  std::memcpy(out, kVoxelsMagic, 8);
  out += 8;
  Put<std::uint32_t>(out, kVoxelsVersion);
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(kRecordSize));
  Put<std::uint64_t>(out, voxels.size());
  writer.stream().write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  for (std::size_t begin = 0; begin < voxels.size() && writer.stream(); begin += kChunkRecords) {
    const std::size_t n = std::min(kChunkRecords, voxels.size() - begin);
    buffer.resize(n * kRecordSize);
    for (std::size_t i = 0; i < n; ++i) PutRecord(voxels[begin + i], buffer.data() + i * kRecordSize);
    writer.stream().write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  }
  return writer.Commit();
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
  meta.insertMeta("georef_latitude_deg", openvdb::DoubleMetadata(g.origin.latitude_deg));
  meta.insertMeta("georef_longitude_deg", openvdb::DoubleMetadata(g.origin.longitude_deg));
  meta.insertMeta("georef_height_m", openvdb::DoubleMetadata(g.origin.height_m));
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
  if (!Read<openvdb::DoubleMetadata>(meta, "georef_latitude_deg", g.origin.latitude_deg))
    return "georef_latitude_deg";
  if (!Read<openvdb::DoubleMetadata>(meta, "georef_longitude_deg", g.origin.longitude_deg))
    return "georef_longitude_deg";
  if (!Read<openvdb::DoubleMetadata>(meta, "georef_height_m", g.origin.height_m)) return "georef_height_m";
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

std::filesystem::path VoxelAttributesFile(const std::filesystem::path& map_file) {
  std::filesystem::path file = map_file;
  return file.replace_extension(".voxels");
}

Status SaveMap(const GlobalMap& map, const std::optional<MapGeoreference>& georef,
               const std::filesystem::path& file) {
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(map);
  // The attributes first: a map.vdb never names records that are not there yet.
  if (Status s = WriteVoxels(impl.voxels, VoxelAttributesFile(file)); !s.ok())
    return Status::Error(file.string() + ": cannot write the map's attributes: " + s.message());
  try {
    openvdb::MetaMap meta;
    WriteMetadata(impl, georef, meta);
    AtomicFileWriter writer(file.string());
    if (Status status = writer.status(); !status.ok()) return status;
    openvdb::io::Stream stream(writer.stream());
    // Blosc (LZ4) when available: several times faster than zip at a similar size.
    if (openvdb::io::Archive::hasBloscCompression())
      stream.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    stream.write(openvdb::GridCPtrVec{impl.index}, meta);  // named "voxel_index" by the map
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
  GlobalMapConfig config;
  GlobalMapStats stats;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::optional<MapGeoreference> georef;
  std::int64_t voxel_count = 0;
  openvdb::Int32Grid::Ptr index;
  try {
    openvdb::io::File vdb(name);
    vdb.open(/*delayLoad=*/false);
    const openvdb::MetaMap::Ptr meta = vdb.getMetadata();
    if (std::string missing = ReadMetadata(*meta, config, stats, origin, georef, voxel_count);
        !missing.empty())
      return Status::Error(name + ": missing or bad metadata '" + missing + "' (not an ultrafusion map?)");
    if (vdb.hasGrid("voxel_index"))
      index = openvdb::gridPtrCast<openvdb::Int32Grid>(vdb.readGrid("voxel_index"));
    vdb.close();
  } catch (const std::exception& e) {
    return Status::Error(name + ": not a readable map file (truncated or corrupt?): " + Printable(e.what()));
  }
  if (Status s = config.Validate(); !s.ok()) return Status::Error(name + ": stored config: " + s.message());
  if (!index) return Status::Error(name + ": grid 'voxel_index' is missing or has the wrong type");
  if (voxel_count < 0 || static_cast<std::uint64_t>(voxel_count) > config.max_voxels ||
      index->activeVoxelCount() != static_cast<openvdb::Index64>(voxel_count))
    return Status::Error(name + ": grid 'voxel_index' has " + std::to_string(index->activeVoxelCount()) +
                         " voxels, the metadata says " + std::to_string(voxel_count) + " (max_voxels " +
                         std::to_string(config.max_voxels) + ")");
  if (std::abs(index->voxelSize()[0] - config.voxel_size_m) > 1e-9 * config.voxel_size_m)
    return Status::Error(name + ": grid 'voxel_index' voxel size differs from voxel_size_m");

  // The attribute records, checked against the index grid: record i must be the voxel whose index is i.
  const std::filesystem::path voxels_file = VoxelAttributesFile(file);
  const std::string voxels_name = voxels_file.string();
  std::ifstream in(voxels_file, std::ios::binary);
  if (!in) return Status::Error(voxels_name + ": cannot open the voxel attributes of " + name);
  char header[kHeaderSize];
  in.read(header, kHeaderSize);
  const char* h = header + 8;
  if (!in || std::memcmp(header, kVoxelsMagic, 8) != 0 || Get<std::uint32_t>(h) != kVoxelsVersion ||
      Get<std::uint32_t>(h) != kRecordSize)
    return Status::Error(voxels_name + ": not a voxel attribute file of this version");
  const std::uint64_t records = Get<std::uint64_t>(h);
  const std::uintmax_t size = std::filesystem::file_size(voxels_file, error);
  if (records != static_cast<std::uint64_t>(voxel_count) || error ||
      size != kHeaderSize + records * kRecordSize)
    return Status::Error(voxels_name + ": holds " + std::to_string(records) + " records in " +
                         std::to_string(size) + " bytes; " + name + " has " + std::to_string(voxel_count) +
                         " voxels (truncated, or from another map?)");
  auto impl = std::make_unique<GlobalMap::Impl>(config);
  impl->stats = stats;
  impl->latest_origin = origin;
  impl->index = index;  // "voxel_index", the map's own name for it
  impl->index->setTransform(VoxelTransform(config.voxel_size_m));
  impl->voxels.reserve(static_cast<std::size_t>(voxel_count));
  auto accessor = impl->index->getConstAccessor();
  std::vector<char> buffer;
  for (std::uint64_t begin = 0; begin < records; begin += kChunkRecords) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunkRecords, records - begin));
    buffer.resize(n * kRecordSize);
    if (!in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())))
      return Status::Error(voxels_name + ": read error at record " + std::to_string(begin));
    for (std::size_t i = 0; i < n; ++i) {
      const VoxelData v = GetRecord(buffer.data() + i * kRecordSize);
      std::int32_t at = -1;
      if (!accessor.probeValue(v.ijk, at) || at != static_cast<std::int32_t>(impl->voxels.size()) ||
          v.count < 1)
        return Status::Error(voxels_name + ": record " + std::to_string(impl->voxels.size()) + " (voxel " +
                             std::to_string(v.ijk.x()) + "," + std::to_string(v.ijk.y()) + "," +
                             std::to_string(v.ijk.z()) + ") does not match " + name + " or has a bad count");
      impl->voxels.push_back(v);
    }
  }
  return LoadedMap{GlobalMapAccess::Wrap(std::move(impl)), georef};
}

}  // namespace uf::mapping
