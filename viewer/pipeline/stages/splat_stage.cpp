#include "viewer/pipeline/stages/splat_stage.h"

#include <optional>

#include "export/exr_view.h"
#include "export/splat_ply.h"
#include "odometry/io/calibration_file.h"
#include "odometry/io/trajectory_file.h"
#include "splat/splat_renderer.h"
#include "splat/views/camera_view_renderer.h"
#include "viewer/pipeline/run_files.h"
#include "viewer/pipeline/splat/splat_views.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// views/camera.yaml, the camera file of `ultrafusion render --camera` (render_camera.h), for a pinhole-radtan
// camera; false for other models.
bool WriteCameraYaml(const fs::path& file, const CameraModel& model, Status& status) {
  if (!dynamic_cast<const PinholeRadtan*>(&model)) return false;
  status = WriteCameraIntrinsicsFile(file, model);
  return true;
}

}  // namespace

std::string SplatSkipReason(const DatasetDescription& description, const SE3& T_output_body) {
  Expected<SplatCameraStream> camera = FindSplatCamera(description, T_output_body);
  return camera ? "" : camera.error();
}

Expected<SplatStageOutput> RunSplatStage(const fs::path& out, const app::SplatConfig& config,
                                         const std::string& device, StageContext& context) {
  context.SetUnit("iterations");
  SplatStageOutput output;
  SplatJobOptions options;
  options.config = config;
  options.device = device;
  SplatJobCallbacks callbacks;
  std::int64_t iterations = 0;
  callbacks.progress = [&](const std::string& phase, std::int64_t done, std::int64_t total,
                           const std::string& unit) {
    if (phase == "train") iterations = done;
    context.SetUnit(unit);
    context.Progress(done, total);
  };
  callbacks.warning = [&](const std::string& warning) { output.notes.push_back("splat: " + warning); };
  Expected<SplatJobResult> result = RunSplatJob(out, options, callbacks);
  context.SetUnit("iterations");
  context.Progress(iterations, iterations);
  if (!result) return result.status();
  for (const std::string& file : result->files)
    if (!file.starts_with("comparisons/")) context.AddOutput(file);
  if (!result->test.empty()) context.AddOutput("comparisons/");
  output.result = std::move(*result);
  return output;
}

Expected<std::string> RunViewsStage(const fs::path& out, const SplatJobResult& splat,
                                    const Eigen::Vector3f& background, const std::string& device,
                                    StageContext& context) {
  context.SetUnit("views");
  const std::vector<StoredView>& views = splat.test;
  Expected<splat::GaussianModel> model = exporting::ReadSplatPly((out / "splats.ply").string());
  if (!model) return model.status();
  Expected<std::unique_ptr<splat::SplatRenderer>> renderer = splat::SplatRenderer::Create({.device = device});
  if (!renderer) return renderer.status();
  if (Status s = (*renderer)->Upload(*model); !s.ok()) return s;
  const fs::path folder = out / "views";
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) return Status::Error(folder.string() + ": cannot create: " + error.message());

  // The camera's own model: a distorted one renders through a covering pinhole and is resampled.
  const CameraModel& camera = *splat.model;
  Expected<splat::CameraViewRenderer> camera_views = splat::CameraViewRenderer::Create(camera);
  if (!camera_views) return camera_views.status();
  splat::RenderSettings settings;
  settings.background = background;
  Trajectory poses;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const SE3& T_world_camera = views[i].camera.T_world_camera;
    Expected<splat::RenderedView> view = camera_views->Render(
        T_world_camera, settings, [&](const splat::SplatCamera& pinhole, const splat::RenderSettings& s) {
          return (*renderer)->Render(pinhole, s);
        });
    if (!view) return view.status();
    const std::string stem = std::to_string(views[i].stamp);
    if (Status s = exporting::WriteViewExr(*view, (folder / (stem + ".exr")).string()); !s.ok()) return s;
    if (Status s = WriteRgbPng(folder / (stem + ".png"), view->rgb, view->width, view->height); !s.ok())
      return s;
    poses.stamps.push_back(views[i].stamp);
    poses.poses.push_back(T_world_camera);
    context.Progress(static_cast<std::int64_t>(i + 1), static_cast<std::int64_t>(views.size()));
  }
  if (Status s = WriteTumTrajectory((folder / "poses.tum").string(), poses); !s.ok()) return s;
  Status camera_written;
  const bool yaml = WriteCameraYaml(folder / "camera.yaml", camera, camera_written);
  if (!camera_written.ok()) return camera_written;
  context.AddOutput("views/ (" + std::to_string(views.size()) + " x .exr, .png; poses.tum" +
                    (yaml ? ", camera.yaml)" : ")"));
  return std::to_string(views.size()) + " held-out views rendered at " + std::to_string(camera.width()) +
         " x " + std::to_string(camera.height()) +
         " px into views/ (EXR: R G B A, Z, depth.expected; PNG previews).";
}

}  // namespace uf::pipeline
