// The map stage of `ultrafusion run`: the keyframes the odometry handed to the KeyframeMapper are all in once
// the last ones are finished; the georeference is the estimator's own (G modes), else the post-hoc alignment
// of the trajectory to the GNSS fixes (odometry/eval/gnss_georeference.h; none without fixes); the report's
// note says which. map.vdb and its voxel attributes are saved. The exports of the map are the next stage's
// (exports_stage.h).
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mapping/keyframe_mapper.h"
#include "mapping/map_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/georeference.h"
#include "odometry/types/trajectory.h"
#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

// What the report says of the map: a one-line summary ("1.2 M points, 64 % coloured, ..."), the files
// written, the mapper's warnings.
struct MapSummary {
  std::string summary, files;
  std::vector<std::string> warnings;
};

struct MapStageInput {
  mapping::KeyframeMapper* mapper = nullptr;
  const DatasetDescription* description = nullptr;
  int gnss_stream = -1;
  RunFrames frames;
  const Trajectory* estimated = nullptr;  // T_world_E
  std::span<const GnssFix> fixes;
  std::optional<Georeference> estimator_georef;  // the map's georeference when set (T_enu_map = T_enu_world)
  std::int64_t keyframes_mapped = 0;
  std::filesystem::path out;
};

struct MapStageOutput {
  std::optional<mapping::MapGeoreference> georef;
  MapSummary map;
  std::vector<std::string> notes;  // the georeference's, or why there is none
};

Expected<MapStageOutput> RunMapStage(const MapStageInput& input, StageContext& context);

}  // namespace uf::pipeline
