// The files of `ultrafusion run`'s map and exports stages: map.vdb, then its exports (map.ply, map.las,
// map.glb, georef.json) in the run folder, summarised for the report; and where the cameras sit relative to
// the estimator's body frame. The georeference from GNSS is odometry/eval/gnss_georeference.h.
#pragma once

#include <filesystem>
#include <optional>

#include "mapping/map_file.h"
#include "odometry/io/dataset_reader.h"
#include "viewer/app/keyframe_mapper.h"
#include "viewer/app/run_report.h"

namespace uf::app {

// The dataset's body frame in the estimator's body frame: LO estimates the LiDAR (T_lidar_body, from the
// LiDAR's T_body_sensor; identity when it has none), LIO the IMU (T_imu_body).
SE3 EstimatorFromBody(const DatasetDescription& description, int lidar_stream, int imu_stream, bool lio);

// The map stage's file: saves map.vdb (and its voxel attributes) and starts report.map (size, colour);
// returns the files written, relative to `out`.
Expected<std::vector<std::string>> SaveRunMap(const std::filesystem::path& out, const KeyframeMapper& mapper,
                                              const std::optional<mapping::MapGeoreference>& georef,
                                              RunReport& report);

// The exports stage: map.ply, map.las, map.glb and georef.json (in ENU when georeferenced, else in the map
// frame); completes report.map. Returns the files written, relative to `out`.
Expected<std::vector<std::string>> WriteRunMapExports(const std::filesystem::path& out,
                                                      const KeyframeMapper& mapper,
                                                      const std::optional<mapping::MapGeoreference>& georef,
                                                      bool mesh, RunReport& report);

}  // namespace uf::app
