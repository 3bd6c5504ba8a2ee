// The map files of a run folder: map.vdb (the global map itself, what `ultrafusion export` reads back) and
// its exports map.ply, map.las, map.glb (points and, optionally, a coloured mesh) with georef.json, shared
// by `ultrafusion run` (at its end) and `ultrafusion export`.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "export/georef.h"
#include "mapping/global_map.h"
#include "mapping/map_file.h"

namespace uf::pipeline {

struct MapExportRequest {
  bool ply = true, las = true, glb = true;
  bool mesh = true;  // a surface mesh in map.glb beside the points (OpenVDB level set; slower on big maps)
  // Grid of the mesh, m (at least the map's voxel): a street mesh at 5 cm is ~3 triangles per map point,
  // 28 M for a 60 s drive, and the glb is built in memory; 0.2 m keeps it ~16x smaller.
  double mesh_voxel_m = 0.2;
  exporting::OutputCrs crs = exporting::OutputCrs::kLocal;
  std::optional<mapping::MapGeoreference> georef;  // needed for enu and utm
};

struct MapExportResult {
  std::vector<std::string> files;  // written, relative to the folder
  std::size_t points = 0;          // map points exported (MapView: seen often enough)
  std::size_t skipped_nonfinite = 0;
  std::size_t mesh_triangles = 0;
  double seconds = 0;
};

// "ply,las,glb" -> the request's format flags; an error names an unknown format.
Status ParseMapFormats(const std::string& list, MapExportRequest& request);

// Writes the requested exports of `map` into `folder`, each atomically. Errors name the file.
Expected<MapExportResult> WriteMapExports(const std::filesystem::path& folder, const mapping::GlobalMap& map,
                                          const MapExportRequest& request);

}  // namespace uf::pipeline
