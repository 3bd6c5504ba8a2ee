#include "viewer/pipeline/stages/map_stage.h"

#include <cstdio>

#include "export/gnss_alignment.h"

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

}  // namespace

std::optional<mapping::MapGeoreference> GeoreferenceFromGnss(const DatasetDescription& description,
                                                             int gnss_stream, const SE3& T_estimator_body,
                                                             const Trajectory& trajectory,
                                                             std::span<const GnssFix> fixes, bool lio,
                                                             std::vector<std::string>& notes) {
  if (gnss_stream < 0 || fixes.empty()) return std::nullopt;
  exporting::GnssAlignmentOptions options;
  const std::optional<SE3>& T_body_antenna =
      description.streams[static_cast<std::size_t>(gnss_stream)].T_body_sensor;
  options.T_body_antenna = T_estimator_body * T_body_antenna.value_or(SE3());
  options.gravity_aligned = lio;
  Expected<exporting::GnssAlignment> aligned = exporting::AlignToGnss(trajectory, fixes, options);
  if (!aligned) {
    notes.push_back("map not georeferenced: " + aligned.status().message());
    return std::nullopt;
  }
  char text[200];
  std::snprintf(text, sizeof(text),
                "map georeferenced by %d GNSS fixes (residual RMS %.2f m): ENU at %.7f, %.7f, %.2f m",
                aligned->fixes_used, aligned->rms_m, aligned->origin.latitude_deg,
                aligned->origin.longitude_deg, aligned->origin.height_m);
  notes.push_back(text);
  return mapping::MapGeoreference{aligned->origin.latitude_deg, aligned->origin.longitude_deg,
                                  aligned->origin.height_m, aligned->T_enu_world};
}

Expected<MapStageOutput> RunMapStage(const MapStageInput& in, StageContext& context) {
  context.SetUnit("keyframes");
  // The odometry stage inserted the keyframes as they left its window; the last ones wait for Finish.
  if (Status s = in.mapper->Finish(); !s.ok()) return s;
  context.Progress(in.keyframes_mapped, in.keyframes_mapped);
  MapStageOutput out;
  out.georef = GeoreferenceFromGnss(*in.description, in.gnss_stream, in.frames.T_estimator_body,
                                    *in.estimated, in.fixes, in.frames.mode == OdometryMode::kLio, out.notes);
  Expected<MapSummary> map = SaveRunMap(in.out, *in.mapper, out.georef);
  if (!map) return map.status();
  out.map = std::move(*map);
  context.AddOutput(mapping::kMapFileName);
  context.AddOutput(mapping::VoxelAttributesFile(mapping::kMapFileName).string());
  return out;
}

}  // namespace uf::pipeline
