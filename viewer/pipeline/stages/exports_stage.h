// The exports stage of `ultrafusion run`: the map's exports (map.ply, map.las, map.glb with the mesh, and
// georef.json) in ENU when the map stage found a georeference, else in the map frame (map_exports.h).
#pragma once

#include <filesystem>
#include <optional>

#include "mapping/keyframe_mapper.h"
#include "viewer/pipeline/map_exports.h"
#include "viewer/pipeline/stage_runner.h"
#include "viewer/pipeline/stages/map_stage.h"

namespace uf::pipeline {

struct ExportsStageInput {
  const mapping::KeyframeMapper* mapper = nullptr;
  std::optional<mapping::MapGeoreference> georef;
  bool mesh = true;
  std::filesystem::path out;
};

Expected<MapExportResult> RunExportsStage(const ExportsStageInput& input, StageContext& context);

// Completes the map stage's summary with the exports: points, mesh, time, files.
void AddExportsToSummary(const MapExportResult& exported, bool mesh, MapSummary& summary);

}  // namespace uf::pipeline
