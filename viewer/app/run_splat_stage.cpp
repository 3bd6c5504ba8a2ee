#include "viewer/app/run_splat_stage.h"

#include <cstdio>
#include <optional>

#include "export/exr_view.h"
#include "export/splat_ply.h"
#include "odometry/io/trajectory_file.h"
#include "splat/splat_renderer.h"
#include "splat/views/camera_view_renderer.h"
#include "viewer/app/run_outputs.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;

SplatSummary Summarize(const SplatJobResult& result) {
  const SplatMetrics& m = result.metrics;
  SplatSummary summary;
  summary.metrics = {
      {"held-out PSNR [dB] (psnr_test)", FormatValue("%.2f", m.test.psnr)},
      {"held-out SSIM (ssim_test)", FormatValue("%.3f", m.test.ssim)},
      {"held-out PSNR of the seeded model [dB]", FormatValue("%.2f", m.psnr_test_initial)},
      {"training PSNR [dB] (psnr_train)", FormatValue("%.2f", m.train.psnr)},
      {"views: training / held out", std::to_string(m.views_train) + " / " + std::to_string(m.views_test)},
      {"iterations", std::to_string(m.iterations) + " of " + std::to_string(m.iterations_planned) +
                         (m.stopped_by_time ? " (time budget reached)" : "")},
      {"iterations per second", FormatValue("%.2f", m.iterations_per_s())},
      {"Gaussians: seeded -> trained",
       std::to_string(m.gaussians_initial) + " -> " + std::to_string(m.gaussians)},
      {"resolution [px]", std::to_string(m.width) + " x " + std::to_string(m.height)},
      {"device", m.device},
      {"camera", m.camera + " (" + std::to_string(m.images) + " images)"}};
  for (const std::string& file : result.files) {
    if (summary.comparison.empty() && file.ends_with("_compare.png")) summary.comparison = file;
    if (file == "plots/splat_loss.png") summary.loss_plot = file;
  }
  return summary;
}

// views/camera.yaml in the format of `ultrafusion render --camera` (render_camera.h), for a pinhole-radtan
// camera; false for other models.
bool WriteCameraYaml(const fs::path& file, const CameraModel& model, Status& status) {
  const auto* radtan = dynamic_cast<const PinholeRadtan*>(&model);
  if (!radtan) return false;
  const PinholeRadtanIntrinsics& k = radtan->intrinsics();
  char text[512];
  std::snprintf(text, sizeof(text),
                "model: pinhole\nwidth: %d\nheight: %d\nfx: %.17g\nfy: %.17g\ncx: %.17g\ncy: %.17g\n"
                "distortion: [%.17g, %.17g, %.17g, %.17g, %.17g]\n",
                model.width(), model.height(), k.pinhole.fx, k.pinhole.fy, k.pinhole.cx, k.pinhole.cy, k.k1,
                k.k2, k.p1, k.p2, k.k3);
  status = WriteTextFileAtomically(file, text);
  return true;
}

}  // namespace

std::string SplatSkipReason(const DatasetDescription& description, const std::string& output_frame) {
  Expected<SplatCameraStream> camera = FindSplatCamera(description, output_frame);
  return camera ? "" : camera.error();
}

Status RunSplatStage(RunState& state, StageContext& context) {
  context.SetUnit("iterations");
  SplatJobOptions options;
  options.config = state.splat_config;
  SplatJobCallbacks callbacks;
  std::int64_t iterations = 0;
  callbacks.progress = [&](const std::string& phase, std::int64_t done, std::int64_t total,
                           const std::string& unit) {
    if (phase == "train") iterations = done;
    context.SetUnit(unit);
    context.Progress(done, total);
  };
  callbacks.warning = [&](const std::string& warning) { state.report.notes.push_back("splat: " + warning); };
  Expected<SplatJobResult> result = RunSplatJob(state.out, options, callbacks);
  context.SetUnit("iterations");
  context.Progress(iterations, iterations);
  if (!result) return result.status();
  for (const std::string& file : result->files)
    if (!file.starts_with("comparisons/")) context.AddOutput(file);
  if (!result->test.empty()) context.AddOutput("comparisons/");
  state.report.splat = Summarize(*result);
  state.splat = std::move(*result);
  return {};
}

Status RunViewsStage(RunState& state, StageContext& context) {
  context.SetUnit("views");
  const std::vector<StoredView>& views = state.splat->test;
  Expected<splat::GaussianModel> model = exporting::ReadSplatPly((state.out / "splats.ply").string());
  if (!model) return model.status();
  Expected<std::unique_ptr<splat::SplatRenderer>> renderer = splat::SplatRenderer::Create();
  if (!renderer) return renderer.status();
  if (Status s = (*renderer)->Upload(*model); !s.ok()) return s;
  const fs::path folder = state.out / "views";
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) return Status::Error(folder.string() + ": cannot create: " + error.message());

  // The camera's own model: a distorted one renders through a covering pinhole and is resampled.
  const CameraModel& camera = *state.splat->model;
  Expected<splat::CameraViewRenderer> camera_views = splat::CameraViewRenderer::Create(camera);
  if (!camera_views) return camera_views.status();
  splat::RenderSettings settings;
  settings.background = state.splat_config.training.render.background;
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
  if (state.report.splat)
    state.report.splat->views = std::to_string(views.size()) + " held-out views rendered at " +
                                std::to_string(camera.width()) + " x " + std::to_string(camera.height()) +
                                " px into views/ (EXR: R G B A, Z, depth.expected; PNG previews).";
  return {};
}

}  // namespace uf::app
