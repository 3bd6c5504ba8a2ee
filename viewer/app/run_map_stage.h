// The files of `ultrafusion run`'s map and exports stages: map.vdb, then its exports (map.ply, map.las,
// map.glb, georef.json) in the run folder, summarised for the report; the georeference from GNSS; and where
// the cameras sit relative to the estimator's body frame.
#pragma once

#include <filesystem>
#include <optional>
#include <span>

#include "mapping/keyframe_mapper.h"
#include "mapping/map_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/trajectory.h"
#include "viewer/app/run_report.h"

namespace uf::app {

// The dataset's body frame in the estimator's body frame: LO estimates the LiDAR (T_lidar_body, from the
// LiDAR's T_body_sensor; identity when it has none), LIO the IMU (T_imu_body).
SE3 EstimatorFromBody(const DatasetDescription& description, int lidar_stream, int imu_stream, bool lio);

// The georeference of the run's map from the GNSS fixes (export/gnss_alignment.h), with the antenna placed
// by the GNSS stream's T_body_sensor; none (and a note why) without fixes or when the alignment is not
// admitted. `trajectory` is in the estimator's body frame; lio: its world is gravity-aligned.
std::optional<mapping::MapGeoreference> GeoreferenceFromGnss(const DatasetDescription& description,
                                                             int gnss_stream, const SE3& T_estimator_body,
                                                             const Trajectory& trajectory,
                                                             std::span<const GnssFix> fixes, bool lio,
                                                             std::vector<std::string>& notes);

// The map stage's file: saves map.vdb (and its voxel attributes) and starts report.map (size, colour);
// returns the files written, relative to `out`.
Expected<std::vector<std::string>> SaveRunMap(const std::filesystem::path& out,
                                              const mapping::KeyframeMapper& mapper,
                                              const std::optional<mapping::MapGeoreference>& georef,
                                              RunReport& report);

// The exports stage: map.ply, map.las, map.glb and georef.json (in ENU when georeferenced, else in the map
// frame); completes report.map. Returns the files written, relative to `out`.
Expected<std::vector<std::string>> WriteRunMapExports(const std::filesystem::path& out,
                                                      const mapping::KeyframeMapper& mapper,
                                                      const std::optional<mapping::MapGeoreference>& georef,
                                                      bool mesh, RunReport& report);

}  // namespace uf::app
