#include "viewer/app/cli/render_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "export/exr_view.h"
#include "export/splat_gltf.h"
#include "export/splat_ply.h"
#include "odometry/io/trajectory_file.h"
#include "splat/splat_renderer.h"
#include "splat/views/camera_view_renderer.h"
#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/render_camera.h"
#include "viewer/pipeline/progress_line.h"
#include "viewer/pipeline/run_render_inputs.h"
#include "viewer/pipeline/splat/splat_outputs.h"

namespace uf::app {

using pipeline::ProgressLine;
using pipeline::RenderInputs;
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RenderArguments {
  std::string input;          // a splat file, or a run folder
  std::string poses, stamps;  // --poses (splat file), --stamps (run folder)
  std::string camera;         // a camera file (splat file), a camera name (run folder)
  std::string out, device;
  int width = 0, height = 0;  // 0: the camera's size
  bool png = false, float_rgba = false;
  std::vector<float> background = {0, 0, 0};
};

Expected<splat::GaussianModel> LoadSplats(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (extension == ".ply") return exporting::ReadSplatPly(path);
  if (extension == ".glb") return exporting::ReadSplatGltf(path);
  return Status::Error(path + ": unknown splat file type '" + extension + "' (expected .ply or .glb)");
}

// The options each form takes: RUN_DIR --stamps [--camera NAME], or SPLATS --poses --camera FILE.
Status CheckForm(const RenderArguments& a) {
  if ((a.width > 0) != (a.height > 0))
    return Status::Error("--width and --height go together (got " + std::to_string(a.width) + " x " +
                         std::to_string(a.height) + ")");
  if (fs::is_directory(a.input)) {
    if (a.stamps.empty()) return Status::Error(a.input + ": a run folder renders at --stamps FILE");
    if (!a.poses.empty()) return Status::Error("--poses: for a splat file; a run folder renders at --stamps");
    return {};
  }
  if (!a.stamps.empty())
    return Status::Error("--stamps: for a run folder; " + a.input + " is a file (render it at --poses)");
  if (a.poses.empty() || a.camera.empty())
    return Status::Error(a.input + ": a splat file renders at --poses FILE through --camera FILE");
  if (!fs::is_regular_file(a.camera)) return Status::Error("--camera: " + a.camera + ": no such file");
  return {};
}

// SPLATS --poses FILE --camera FILE: the poses as the file gives them, T_world_camera.
Expected<RenderInputs> SplatFileInputs(const RenderArguments& a, const RenderCamera& camera) {
  Expected<Trajectory> poses = ReadTumTrajectory(a.poses);
  if (!poses) return poses.status();
  if (poses->empty()) return Status::Error(a.poses + ": no poses");
  return RenderInputs{.splats = a.input,
                      .camera_name = "",
                      .camera = camera.model,
                      .stamps = std::move(poses->stamps),
                      .T_world_camera = std::move(poses->poses)};
}

int Render(const RenderArguments& a, const RenderInputs& inputs) {
  std::shared_ptr<const CameraModel> camera = inputs.camera;
  if (a.width > 0) {
    Expected<std::shared_ptr<const CameraModel>> resized = ResizeCameraModel(*camera, a.width, a.height);
    if (!resized) return ReportUsageError(resized.status());
    camera = *resized;
  }
  Expected<splat::GaussianModel> model = LoadSplats(inputs.splats.string());
  if (!model) return ReportError(model.status());
  splat::SplatRendererOptions options;
  options.device = a.device;
  Expected<std::unique_ptr<splat::SplatRenderer>> renderer = splat::SplatRenderer::Create(options);
  if (!renderer) return ReportError(renderer.status());
  if (Status s = (*renderer)->Upload(*model); !s.ok()) return ReportError(s);

  splat::RenderSettings settings;
  settings.background = Eigen::Vector3f(a.background[0], a.background[1], a.background[2]);
  // Distorted cameras render through a covering pinhole, resampled (splat/views/camera_view_renderer.h).
  Expected<splat::CameraViewRenderer> camera_views = splat::CameraViewRenderer::Create(*camera);
  if (!camera_views) return ReportError(camera_views.status());
  std::error_code error;
  fs::create_directories(a.out, error);
  if (error) return ReportError(Status::Error(a.out + ": cannot create the folder: " + error.message()));

  const exporting::ExrPixelType pixel_type =
      a.float_rgba ? exporting::ExrPixelType::kFloat : exporting::ExrPixelType::kHalf;
  const std::size_t views = inputs.stamps.size();
  double render_ms = 0;
  {
    ProgressLine progress("render");
    for (std::size_t i = 0; i < views; ++i) {
      Expected<splat::RenderedView> view = camera_views->Render(
          inputs.T_world_camera[i], settings,
          [&](const splat::SplatCamera& pinhole, const splat::RenderSettings& s) {
            const Clock::time_point start = Clock::now();
            Expected<splat::RenderedView> rendered = (*renderer)->Render(pinhole, s);
            render_ms += std::chrono::duration<double, std::milli>(Clock::now() - start).count();
            return rendered;
          });
      if (!view) return ReportError(view.status());
      // Files are named by the stamp in nanoseconds, like the frames of a dataset.
      const std::string name = std::to_string(inputs.stamps[i]);
      if (Status s = exporting::WriteViewExr(*view, (fs::path(a.out) / (name + ".exr")).string(), pixel_type);
          !s.ok())
        return ReportError(s);
      if (a.png)
        // 8-bit preview of the display-referred colour (already composited over the background).
        if (Status s = pipeline::WriteRgbPng(fs::path(a.out) / (name + ".png"), view->rgb, view->width,
                                             view->height);
            !s.ok())
          return ReportError(s);
      progress.Update("views", static_cast<std::int64_t>(i + 1), static_cast<std::int64_t>(views));
    }
  }
  std::printf("render: %zu views of %d x %d px, %zu Gaussians on %s, %.1f ms/view\n", views, camera->width(),
              camera->height(), model->size(), (*renderer)->device_name().c_str(), render_ms / views);
  if (!inputs.camera_name.empty())
    std::printf("  camera %s of %s, placed on its trajectory.tum\n", inputs.camera_name.c_str(),
                a.input.c_str());
  std::printf("  wrote %s: <stamp ns>.exr (R G B A, Z, %s)%s\n", a.out.c_str(),
              exporting::kExrExpectedDepthChannel, a.png ? " and <stamp ns>.png" : "");
  return kExitOk;
}

int RunRender(const RenderArguments& a) {
  if (Status s = CheckForm(a); !s.ok()) return ReportUsageError(s);
  if (fs::is_directory(a.input)) {
    Expected<RenderInputs> inputs = pipeline::ReadRunRenderInputs(a.input, a.stamps, a.camera);
    if (!inputs) return ReportError(inputs.status());
    return Render(a, *inputs);
  }
  Expected<RenderCamera> camera = LoadRenderCamera(a.camera);  // the user's file: a usage error
  if (!camera) return ReportUsageError(camera.status());
  Expected<RenderInputs> inputs = SplatFileInputs(a, *camera);
  if (!inputs) return ReportError(inputs.status());
  return Render(a, *inputs);
}

}  // namespace

Subcommand AddRenderCommand(CLI::App& app) {
  auto a = std::make_shared<RenderArguments>();
  CLI::App* command = app.add_subcommand(
      "render",
      "Render Gaussian splats (3DGS .ply or KHR_gaussian_splatting .glb, or a run's) to EXR views, headless");
  command
      ->add_option("SPLATS_OR_RUN_DIR", a->input,
                   "Splat file (3DGS .ply or .glb), or the folder of an `ultrafusion run` with splats")
      ->required()
      ->check(CLI::ExistingPath);
  command
      ->add_option("--poses", a->poses,
                   "Splat file: TUM file of T_world_camera (camera axes x right, y down, z forward)")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--stamps", a->stamps,
                   "Run folder: times to render the run's camera at, seconds, one per line ('#' comments); "
                   "the pose is interpolated on trajectory.tum")
      ->check(CLI::ExistingFile);
  command->add_option(
      "--camera", a->camera,
      "Splat file: camera YAML (distortion_model: radial-tangential, intrinsics: [fx, fy, cx, "
      "cy], distortion_coefficients: [k1, k2, p1, p2], resolution: [width, height]). Run "
      "folder: the camera's stream name (default: the first camera of its cameras.yaml)");
  command->add_option("--out", a->out, "Output folder (created; views are named by stamp in ns)")->required();
  command->add_option("--width", a->width, "Output width, px (with --height; intrinsics scaled)")
      ->check(CLI::Range(1, 16384));
  command->add_option("--height", a->height, "Output height, px (with --width)")->check(CLI::Range(1, 16384));
  command->add_flag("--png", a->png, "Also write an 8-bit PNG preview per view");
  command->add_flag("--float", a->float_rgba, "R G B A as 32-bit float (default: half)");
  command->add_option("--background", a->background, "Background colour R G B in [0, 1]")
      ->expected(3)
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  command->add_option(
      "--device", a->device,
      "Vulkan device: index or part of its name (default: a GPU if any, else lavapipe on the CPU)");
  return {command, [a] { return RunRender(*a); }};
}

}  // namespace uf::app
