#include "viewer/pipeline/stages/map_stage.h"

#include <cstdio>

#include "odometry/eval/gnss_georeference.h"

namespace uf::pipeline {
namespace {

// Saves map.vdb (and its voxel attributes) and summarises it.
Expected<MapSummary> SaveRunMap(const std::filesystem::path& out, const mapping::KeyframeMapper& mapper,
                                const std::optional<mapping::MapGeoreference>& georef) {
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
  return summary;
}

// The fallback: the trajectory aligned to the fixes after the run.
std::optional<mapping::MapGeoreference> PostHocGeoreference(const MapStageInput& in,
                                                            std::vector<std::string>& notes) {
  const std::optional<SE3> T_body_gnss =
      in.gnss_stream < 0 ? std::nullopt
                         : in.description->streams[static_cast<std::size_t>(in.gnss_stream)].T_body_sensor;
  const GnssGeoreference found = GeoreferenceFromGnss(
      *in.estimated, in.fixes, T_body_gnss, in.frames.T_estimator_body, in.frames.mode == OdometryMode::kLio);
  if (!found.note.empty())
    notes.push_back(found.note + " (post-hoc alignment of the trajectory to the fixes)");
  if (!found.alignment) return std::nullopt;
  return mapping::MapGeoreference{found.alignment->origin, found.alignment->T_enu_world};
}

}  // namespace

Expected<MapStageOutput> RunMapStage(const MapStageInput& in, StageContext& context) {
  context.SetUnit("keyframes");
  // The odometry stage inserted the keyframes as they left its window; the last ones wait for Finish.
  if (Status s = in.mapper->Finish(); !s.ok()) return s;
  context.Progress(in.keyframes_mapped, in.keyframes_mapped);
  MapStageOutput out;
  if (in.estimator_georef) {
    out.georef = mapping::MapGeoreference{in.estimator_georef->origin, in.estimator_georef->T_enu_world};
    out.notes.push_back("map georeferenced by the estimator's GNSS alignment (trajectory.tum is in ENU)");
  } else {
    out.georef = PostHocGeoreference(in, out.notes);
  }
  Expected<MapSummary> map = SaveRunMap(in.out, *in.mapper, out.georef);
  if (!map) return map.status();
  out.map = std::move(*map);
  context.AddOutput(mapping::kMapFileName);
  context.AddOutput(mapping::VoxelAttributesFile(mapping::kMapFileName).string());
  return out;
}

}  // namespace uf::pipeline
