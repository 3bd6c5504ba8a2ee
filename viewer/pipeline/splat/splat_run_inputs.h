// What splat training reads from a run folder besides run.json (run/run_record.h): the dataset's reader
// configuration (config.yaml's dataset: section), trajectory.tum, and the Gaussians seeded from map.vdb.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"
#include "splat/seeding.h"
#include "viewer/app/config/dataset_config.h"

namespace uf::pipeline {

using app::DatasetConfig;

// The dataset: section of folder/config.yaml (the defaults when the run saved none).
Expected<DatasetConfig> RunDatasetConfig(const std::filesystem::path& folder);

// A TUM trajectory with at least two poses; errors name the file (and the line, for bad values).
Expected<Trajectory> ReadSplatTrajectory(const std::filesystem::path& file);

// Gaussians seeded from folder/map.vdb (mapping::LoadMap, mapping::MapView, splat::SeedGaussians, default
// seed options at `sh_degree`). An error names a missing or unreadable map, or an empty one.
Expected<splat::SeedResult> SeedFromRunMap(const std::filesystem::path& folder, int sh_degree,
                                           std::size_t max_gaussians);

}  // namespace uf::pipeline
