// The end of `ultrafusion run`'s map stage: map.vdb and its exports (map.ply, map.las, map.glb,
// georef.json) in the run folder, summarised for the report; and where the cameras sit relative to the
// estimator's body frame.
#pragma once

#include <filesystem>
#include <optional>
#include <span>

#include "mapping/map_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/trajectory.h"
#include "viewer/app/keyframe_mapper.h"
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

// Saves map.vdb and writes the exports (in ENU when georeferenced, else in the map frame); fills report.map.
Status WriteRunMap(const std::filesystem::path& out, const KeyframeMapper& mapper,
                   const std::optional<mapping::MapGeoreference>& georef, bool mesh, RunReport& report);

}  // namespace uf::app
