#include "viewer/pipeline/stages/exports_stage.h"

#include <cstdio>

namespace uf::pipeline {

Expected<MapExportResult> RunExportsStage(const ExportsStageInput& in, StageContext& context) {
  context.SetUnit("files");
  MapExportRequest request;
  request.mesh = in.mesh;
  request.georef = in.georef;
  if (in.georef) request.crs = exporting::OutputCrs::kEnu;
  Expected<MapExportResult> exported = WriteMapExports(in.out, in.mapper->map(), request);
  if (!exported) return exported.status();
  for (const std::string& file : exported->files) context.AddOutput(file);
  const auto files = static_cast<std::int64_t>(exported->files.size());
  context.Progress(files, files);
  return exported;
}

void AddExportsToSummary(const MapExportResult& exported, bool mesh, MapSummary& summary) {
  char mesh_text[64] = "no mesh";
  if (mesh) std::snprintf(mesh_text, sizeof(mesh_text), "mesh %zu triangles", exported.mesh_triangles);
  char text[160];
  std::snprintf(text, sizeof(text), "; %zu points exported, %s, exports %.1f s", exported.points, mesh_text,
                exported.seconds);
  summary.summary += text;
  for (const std::string& file : exported.files) summary.files += ", " + file;
}

}  // namespace uf::pipeline
