#include "viewer/app/cli/export_command.h"

#include <cstdio>
#include <filesystem>
#include <memory>

#include "viewer/app/cli/exit_codes.h"
#include "viewer/pipeline/map_exports.h"

namespace uf::app {

using pipeline::MapExportRequest;
using pipeline::MapExportResult;
using pipeline::ParseMapFormats;
using pipeline::WriteMapExports;
namespace {

namespace fs = std::filesystem;

struct ExportArguments {
  std::string run_dir, out, formats = "ply,las,glb", crs = "local";
  bool no_mesh = false;
};

int RunExport(const ExportArguments& a) {
  MapExportRequest request;
  if (Status s = ParseMapFormats(a.formats, request); !s.ok()) return ReportUsageError(s);
  request.mesh = !a.no_mesh;
  request.crs = a.crs == "enu"   ? exporting::OutputCrs::kEnu
                : a.crs == "utm" ? exporting::OutputCrs::kUtm
                                 : exporting::OutputCrs::kLocal;
  const fs::path map_file = fs::path(a.run_dir) / mapping::kMapFileName;
  std::error_code error;
  if (!fs::exists(map_file, error))
    return ReportError(
        Status::Error(map_file.string() + ": no map in the run folder (was it run with --no-map?)"));
  Expected<mapping::LoadedMap> loaded = mapping::LoadMap(map_file);
  if (!loaded) return ReportError(loaded.status());
  request.georef = loaded->georef;
  const fs::path out = a.out.empty() ? fs::path(a.run_dir) : fs::path(a.out);
  fs::create_directories(out, error);
  if (error)
    return ReportError(Status::Error(out.string() + ": cannot create the folder: " + error.message()));
  Expected<MapExportResult> result = WriteMapExports(out, loaded->map, request);
  if (!result) return ReportError(result.status());
  std::printf("export: %zu map points (%s frame), %zu mesh triangles, %.1f s\n", result->points,
              a.crs.c_str(), result->mesh_triangles, result->seconds);
  if (result->skipped_nonfinite > 0)
    std::printf("  skipped %zu non-finite points\n", result->skipped_nonfinite);
  std::string files;
  for (const std::string& f : result->files) files += (files.empty() ? "" : ", ") + f;
  std::printf("  wrote %s: %s\n", out.string().c_str(), files.c_str());
  return kExitOk;
}

}  // namespace

Subcommand AddExportCommand(CLI::App& app) {
  auto a = std::make_shared<ExportArguments>();
  CLI::App* command =
      app.add_subcommand("export", "Write a run's map (map.vdb, map.voxels) as PLY, LAS 1.4 and glTF");
  command
      ->add_option("RUN_DIR", a->run_dir, "Output folder of `ultrafusion run` (holds map.vdb and map.voxels)")
      ->required();
  command->add_option("--format", a->formats, "Comma-separated: ply, las, glb")->capture_default_str();
  command
      ->add_option("--crs", a->crs,
                   "Frame of the coordinates: local (the map frame), enu or utm (need a georeferenced map)")
      ->check(CLI::IsMember({"local", "enu", "utm"}))
      ->capture_default_str();
  command->add_option("--out", a->out, "Folder for the files (default: RUN_DIR)");
  command->add_flag("--no-mesh", a->no_mesh, "No surface mesh in map.glb");
  return {command, [a] { return RunExport(*a); }};
}

}  // namespace uf::app
