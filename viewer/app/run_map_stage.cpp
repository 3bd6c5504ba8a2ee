#include "viewer/app/run_map_stage.h"

#include <cstdio>

#include "viewer/app/map_exports.h"

namespace uf::app {

SE3 EstimatorFromBody(const DatasetDescription& description, int lidar_stream, int imu_stream, bool lio) {
  const int stream = lio ? imu_stream : lidar_stream;
  if (stream < 0) return SE3();
  const std::optional<SE3>& T_body_sensor =
      description.streams[static_cast<std::size_t>(stream)].T_body_sensor;
  return T_body_sensor ? T_body_sensor->inverse() : SE3();
}

Expected<std::vector<std::string>> SaveRunMap(const std::filesystem::path& out, const KeyframeMapper& mapper,
                                              const std::optional<mapping::MapGeoreference>& georef,
                                              RunReport& report) {
  const mapping::GlobalMap& map = mapper.map();
  if (Status s = mapping::SaveMap(map, georef, out / mapping::kMapFileName); !s.ok()) return s;
  const mapping::GlobalMapStats stats = map.stats();
  char colour[96] = "uncoloured (no usable camera image)";
  if (mapper.in_footprint_points() > 0)
    std::snprintf(colour, sizeof(colour), "%.1f %% of the in-image points coloured",
                  100.0 * mapper.colored_points() / mapper.in_footprint_points());
  char text[200];
  std::snprintf(text, sizeof(text), "%zu voxels (%.3g m), %s, %s frame", stats.voxels,
                map.config().voxel_size_m, colour, georef ? "ENU" : "map (local)");
  MapSummary summary;
  summary.summary = text;
  summary.files = std::string(mapping::kMapFileName) + ", " +
                  mapping::VoxelAttributesFile(mapping::kMapFileName).string();
  summary.warnings = mapper.warnings();
  report.map = std::move(summary);
  return std::vector<std::string>{std::string(mapping::kMapFileName),
                                  mapping::VoxelAttributesFile(mapping::kMapFileName).string()};
}

Expected<std::vector<std::string>> WriteRunMapExports(const std::filesystem::path& out,
                                                      const KeyframeMapper& mapper,
                                                      const std::optional<mapping::MapGeoreference>& georef,
                                                      bool mesh, RunReport& report) {
  MapExportRequest request;
  request.mesh = mesh;
  request.georef = georef;
  if (georef) request.crs = exporting::OutputCrs::kEnu;
  Expected<MapExportResult> exported = WriteMapExports(out, mapper.map(), request);
  if (!exported) return exported.status();
  char mesh_text[64] = "no mesh";
  if (mesh) std::snprintf(mesh_text, sizeof(mesh_text), "mesh %zu triangles", exported->mesh_triangles);
  char text[160];
  std::snprintf(text, sizeof(text), "; %zu points exported, %s, exports %.1f s", exported->points, mesh_text,
                exported->seconds);
  if (report.map) {
    report.map->summary += text;
    for (const std::string& file : exported->files) report.map->files += ", " + file;
  }
  return exported->files;
}

}  // namespace uf::app
