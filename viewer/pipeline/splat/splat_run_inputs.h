// What splat training reads from a run folder: run.json (which dataset the run read, in which mode and
// output frame: written by `ultrafusion run` beside config.yaml), the dataset's reader configuration
// (config.yaml's dataset: section), trajectory.tum, and the Gaussians seeded from map.vdb.
//
// run.json: {"dataset": "/abs/path", "output_frame": "lidar" | "imu", "mode": "lo" | "lio",
//            "map_from": "odometry" | "trajectory"}  (trajectory: `run --from map` remade the map from
// trajectory.tum, which puts it in the trajectory's world; see splat_camera_poses.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"
#include "splat/seeding.h"
#include "viewer/app/dataset_config.h"

namespace uf::app {

inline constexpr const char* kRunJsonFile = "run.json";

struct RunInfo {
  std::string dataset;                // absolute path
  std::string output_frame;           // of trajectory.tum: "lidar" or "imu"
  std::string mode;                   // "lo" or "lio"
  std::string map_from = "odometry";  // "odometry" or "trajectory"
};

// Writes folder/run.json atomically.
Status WriteRunJson(const std::filesystem::path& folder, const RunInfo& info);

// Reads folder/run.json; a folder without one gets an error that says to re-run `ultrafusion run`.
Expected<RunInfo> ReadRunJson(const std::filesystem::path& folder);

// The dataset: section of folder/config.yaml (the defaults when the run saved none).
Expected<DatasetConfig> RunDatasetConfig(const std::filesystem::path& folder);

// A TUM trajectory with at least two poses; errors name the file (and the line, for bad values).
Expected<Trajectory> ReadSplatTrajectory(const std::filesystem::path& file);

// Gaussians seeded from folder/map.vdb (mapping::LoadMap, mapping::MapView, splat::SeedGaussians, default
// seed options at `sh_degree`). An error names a missing or unreadable map, or an empty one.
Expected<splat::SeedResult> SeedFromRunMap(const std::filesystem::path& folder, int sh_degree,
                                           std::size_t max_gaussians);

}  // namespace uf::app
