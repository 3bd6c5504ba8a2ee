#include "viewer/pipeline/splat/splat_run_inputs.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "mapping/map_file.h"
#include "mapping/map_view.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/trajectory_file.h"

namespace uf::app {

namespace fs = std::filesystem;

Status WriteRunJson(const fs::path& folder, const RunInfo& info) {
  const nlohmann::json json = {{"dataset", info.dataset},
                               {"output_frame", info.output_frame},
                               {"mode", info.mode},
                               {"map_from", info.map_from}};
  AtomicFileWriter writer((folder / kRunJsonFile).string());
  if (Status s = writer.status(); !s.ok()) return s;
  writer.stream() << json.dump(2) << "\n";
  return writer.Commit();
}

Expected<RunInfo> ReadRunJson(const fs::path& folder) {
  const fs::path path = folder / kRunJsonFile;
  std::error_code error;
  if (!fs::exists(path, error))
    return Status::Error(path.string() +
                         ": missing; it names the dataset the run read (re-run `ultrafusion " +
                         "run` on the dataset: runs made before it was written have none)");
  std::ifstream in(path);
  nlohmann::json json;
  try {
    in >> json;
  } catch (const nlohmann::json::exception& e) {
    return Status::Error(path.string() + ": not valid JSON: " + e.what());
  }
  RunInfo info;
  for (auto [key, field] : {std::pair<const char*, std::string*>{"dataset", &info.dataset},
                            {"output_frame", &info.output_frame},
                            {"mode", &info.mode},
                            {"map_from", &info.map_from}}) {
    if (!json.is_object() || !json.contains(key) || !json[key].is_string())
      return Status::Error(path.string() + ": '" + key + "' missing or not a string");
    *field = json[key].get<std::string>();
  }
  if (info.output_frame != "lidar" && info.output_frame != "imu")
    return Status::Error(path.string() + ": output_frame '" + info.output_frame +
                         "' (expected lidar or imu)");
  if (info.mode != "lo" && info.mode != "lio")
    return Status::Error(path.string() + ": mode '" + info.mode + "' (expected lo or lio)");
  if (info.map_from != "odometry" && info.map_from != "trajectory")
    return Status::Error(path.string() + ": map_from '" + info.map_from +
                         "' (expected odometry or trajectory)");
  return info;
}

Expected<DatasetConfig> RunDatasetConfig(const fs::path& folder) {
  std::error_code error;
  if (!fs::exists(folder / "config.yaml", error)) return DatasetConfig{};
  return LoadDatasetConfig(folder / "config.yaml");
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

}  // namespace uf::app
