#include "viewer/pipeline/map_exports.h"

#include <algorithm>
#include <chrono>
#include <sstream>

#include "export/gltf_writer.h"
#include "export/las_writer.h"
#include "export/ply_writer.h"
#include "mapping/map_view.h"
#include "mapping/meshing.h"

namespace uf::pipeline {

Status ParseMapFormats(const std::string& list, MapExportRequest& request) {
  request.ply = request.las = request.glb = false;
  std::istringstream items(list);
  for (std::string item; std::getline(items, item, ',');) {
    if (item == "ply")
      request.ply = true;
    else if (item == "las")
      request.las = true;
    else if (item == "glb")
      request.glb = true;
    else
      return Status::Error("--format: unknown format '" + item + "' (expected ply, las, glb)");
  }
  if (!request.ply && !request.las && !request.glb) return Status::Error("--format: no format given");
  return {};
}

Expected<MapExportResult> WriteMapExports(const std::filesystem::path& folder, const mapping::GlobalMap& map,
                                          const MapExportRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<exporting::Georeference> georef;
  if (request.georef) {
    Expected<exporting::Georeference> created = exporting::Georeference::Create(request.georef->origin);
    if (!created) return created.status();
    georef = *created;
  }
  if (request.crs != exporting::OutputCrs::kLocal && !georef)
    return Status::Error(std::string("--crs ") + exporting::OutputCrsName(request.crs) +
                         ": the map has no georeference (no GNSS); use --crs local");
  const exporting::Georeference* geo = georef ? &*georef : nullptr;
  const mapping::MapView map_view(map);
  // enu / utm: the map frame moved into the ENU frame it was aligned to (identity when built in it).
  const SE3 T_out_map = request.crs != exporting::OutputCrs::kLocal ? request.georef->T_enu_map : SE3();
  const mapping::TransformedPointSource view(map_view, T_out_map);
  MapExportResult result;
  result.points = view.size();
  exporting::ExportStats stats;
  if (request.ply) {
    if (Status s = exporting::WritePly(folder / "map.ply", view, {.crs = request.crs, .georef = geo}, &stats);
        !s.ok())
      return s;
    result.files.push_back("map.ply");
    result.skipped_nonfinite = stats.points_skipped_nonfinite;
  }
  if (request.las) {
    exporting::LasOptions options;
    options.crs = request.crs;
    options.georef = geo;
    if (Status s = exporting::WriteLas(folder / "map.las", view, options); !s.ok()) return s;
    result.files.push_back("map.las");
  }
  if (request.glb) {
    std::optional<mapping::ColoredMesh> mesh;
    if (request.mesh) {
      mapping::MeshOptions options;
      options.voxel_size_m = std::max(request.mesh_voxel_m, map.config().voxel_size_m);
      Expected<mapping::ColoredMesh> meshed = mapping::MeshFromMap(view, options);
      if (!meshed) return meshed.status();
      result.mesh_triangles = meshed->triangles.size();
      for (Eigen::Vector3d& v : meshed->vertices) v = T_out_map * v;
      for (Eigen::Vector3f& n : meshed->normals) n = T_out_map.rotation().cast<float>() * n;
      if (!meshed->empty()) mesh = std::move(*meshed);
    }
    exporting::GltfOptions options;
    options.crs = request.crs;
    options.georef = geo;
    if (Status s = exporting::WriteGlb(folder / "map.glb", &view, mesh ? &*mesh : nullptr, options); !s.ok())
      return s;
    result.files.push_back("map.glb");
  }
  if (Status s =
          exporting::WriteGeorefJson(folder / "georef.json", georef, request.crs, Eigen::Vector3d::Zero());
      !s.ok())
    return s;
  result.files.push_back("georef.json");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace uf::pipeline
