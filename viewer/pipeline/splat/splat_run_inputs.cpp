#include "viewer/pipeline/splat/splat_run_inputs.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "mapping/map_file.h"
#include "mapping/map_view.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/trajectory_file.h"
#include "viewer/app/config/config_file.h"

namespace uf::pipeline {

namespace fs = std::filesystem;

Expected<DatasetConfig> RunDatasetConfig(const fs::path& folder) {
  std::error_code error;
  if (!fs::exists(folder / "config.yaml", error)) return DatasetConfig{};
  Expected<app::ConfigFile> config = app::LoadConfigFile(folder / "config.yaml");
  if (!config) return config.status();
  return config->dataset;
}

Expected<Trajectory> ReadSplatTrajectory(const fs::path& file) {
  std::error_code error;
  if (!fs::exists(file, error)) return Status::Error(file.string() + ": missing (the run's trajectory)");
  Expected<Trajectory> trajectory = ReadTumTrajectory(file.string());
  if (!trajectory) return trajectory.status();
  if (trajectory->size() < 2)
    return Status::Error(file.string() + ": " + std::to_string(trajectory->size()) +
                         " poses; at least two are needed to place the images");
  return trajectory;
}

Expected<splat::SeedResult> SeedFromRunMap(const fs::path& folder, int sh_degree, std::size_t max_gaussians) {
  const fs::path file = folder / mapping::kMapFileName;
  std::error_code error;
  if (!fs::exists(file, error))
    return Status::Error(file.string() + ": missing; the splats are seeded from the run's map (run " +
                         "`ultrafusion run` without --no-map)");
  Expected<mapping::LoadedMap> loaded = mapping::LoadMap(file);
  if (!loaded) return loaded.status();
  const mapping::MapView view(loaded->map);
  if (view.size() == 0) return Status::Error(file.string() + ": the map has no points to seed splats from");
  splat::SeedOptions options;
  options.sh_degree = sh_degree;
  options.max_gaussians = max_gaussians;
  return splat::SeedGaussians(view, options);
}

}  // namespace uf::pipeline
