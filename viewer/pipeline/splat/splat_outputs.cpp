#include "viewer/pipeline/splat/splat_outputs.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "export/exr_view.h"
#include "export/splat_gltf.h"
#include "export/splat_ply.h"
#include "odometry/eval/plots.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/image_decode.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// JSON has no infinity: identical images (PSNR +inf) are written as null.
nlohmann::json Number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
}

}  // namespace

Status WriteSplatMetrics(const fs::path& file, const SplatMetrics& m) {
  nlohmann::json views = nlohmann::json::array();
  for (const ViewScore& v : m.test.views)
    views.push_back({{"stamp_ns", v.stamp}, {"psnr", Number(v.psnr)}, {"ssim", v.ssim}});
  nlohmann::json exposures = nlohmann::json::array();
  for (const ViewExposure& v : m.exposures)
    exposures.push_back({{"stamp_ns", v.stamp},
                         {"held_out", v.held_out},
                         {"gain", v.exposure.gain},
                         {"bias", v.exposure.bias}});
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, seconds] : m.stage_seconds) stages[name] = seconds;
  nlohmann::json sizes = nlohmann::json::array();
  for (const TrainingSize& s : m.sizes)
    sizes.push_back({{"resolution", {s.width, s.height}},
                     {"iterations", s.iterations},
                     {"seconds", s.seconds},
                     {"iterations_per_s", s.seconds > 0 ? s.iterations / s.seconds : 0.0}});
  const nlohmann::json json = {{"psnr_test", Number(m.test.psnr)},
                               {"ssim_test", m.test.ssim},
                               {"psnr_test_initial", Number(m.psnr_test_initial)},
                               {"psnr_train", Number(m.train.psnr)},
                               {"ssim_train", m.train.ssim},
                               {"iterations", m.iterations},
                               {"iterations_planned", m.iterations_planned},
                               {"iterations_per_s", m.iterations_per_s()},
                               {"seconds", m.seconds},
                               {"stopped_by", m.stopped_by_time ? "time_budget" : "iterations"},
                               {"gaussians", m.gaussians},
                               {"gaussians_initial", m.gaussians_initial},
                               {"map_seeds", m.map_seeds},
                               {"feature_seeds", m.feature_seeds},
                               {"sky_gaussians", m.sky_gaussians},
                               {"uncoloured_seeds", m.uncoloured_seeds},
                               {"unseen_map_points", m.unseen_map_points},
                               {"device", m.device},
                               {"camera", m.camera},
                               {"resolution", {m.width, m.height}},
                               {"views_train", m.views_train},
                               {"views_test", m.views_test},
                               {"images", m.images},
                               {"images_outside_trajectory", m.images_outside_trajectory},
                               {"images_undecodable", m.images_undecodable},
                               {"masked_pixels", m.masked_pixels},
                               {"scene_extent_m", m.scene_extent_m},
                               {"sh_degree", m.sh_degree},
                               {"test_views", views},
                               {"exposure_compensation", m.exposure_compensation},
                               {"exposures", exposures},
                               {"stage_seconds", stages},
                               {"sizes", sizes}};
  AtomicFileWriter writer(file.string());
  if (Status s = writer.status(); !s.ok()) return s;
  writer.stream() << json.dump(2) << "\n";
  return writer.Commit();
}

Expected<std::vector<std::string>> WriteSplatFiles(const fs::path& folder,
                                                   const splat::GaussianModel& model) {
  if (Status s = exporting::WriteSplatPly(model, (folder / "splats.ply").string()); !s.ok()) return s;
  if (Status s = exporting::WriteSplatGlb(model, (folder / "splats.glb").string()); !s.ok()) return s;
  return std::vector<std::string>{"splats.ply", "splats.glb"};
}

Status WriteRgbPng(const fs::path& file, const std::vector<float>& rgb, int width, int height) {
  Image image;
  image.width = width, image.height = height, image.channels = 3;
  image.pixels.resize(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i)
    image.pixels[i] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(rgb[i], 0.0f, 1.0f)));
  Expected<std::vector<std::uint8_t>> png = EncodePng(image, file.string());
  if (!png) return png.status();
  return WriteBinaryFileAtomically(file, *png);
}

Expected<std::vector<std::string>> WriteComparisons(const fs::path& folder,
                                                    const std::vector<StoredView>& views,
                                                    const std::vector<splat::RenderedView>& renders) {
  std::vector<std::string> files;
  if (renders.empty()) return files;
  std::error_code error;
  fs::create_directories(folder / "comparisons", error);
  if (error) return Status::Error((folder / "comparisons").string() + ": cannot create: " + error.message());
  for (std::size_t i = 0; i < renders.size() && i < views.size(); ++i) {
    const splat::RenderedView& rendered = renders[i];
    const splat::TrainingView real = ToTrainingView(views[i]);
    const int w = rendered.width, h = rendered.height;
    // real | rendered, side by side.
    std::vector<float> both(6 * static_cast<std::size_t>(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const std::size_t at = 3 * (static_cast<std::size_t>(y) * w + x) + c;
          both[3 * (static_cast<std::size_t>(y) * 2 * w + x) + c] = real.rgb[at];
          both[3 * (static_cast<std::size_t>(y) * 2 * w + w + x) + c] = rendered.rgb[at];
        }
    const std::string stem = "comparisons/" + std::to_string(views[i].stamp);
    if (Status s = WriteRgbPng(folder / (stem + "_render.png"), rendered.rgb, w, h); !s.ok()) return s;
    if (Status s = WriteRgbPng(folder / (stem + "_real.png"), real.rgb, w, h); !s.ok()) return s;
    if (Status s = WriteRgbPng(folder / (stem + "_compare.png"), both, 2 * w, h); !s.ok()) return s;
    if (Status s = exporting::WriteViewExr(rendered, (folder / (stem + ".exr")).string()); !s.ok()) return s;
    for (const char* suffix : {"_render.png", "_real.png", "_compare.png", ".exr"})
      files.push_back(stem + suffix);
  }
  return files;
}

Expected<std::vector<std::string>> WriteLossPlot(const fs::path& folder, const std::vector<double>& loss) {
  if (loss.size() < 2) return std::vector<std::string>{};
  std::error_code error;
  fs::create_directories(folder / "plots", error);
  if (error) return Status::Error((folder / "plots").string() + ": cannot create: " + error.message());
  std::vector<double> iteration(loss.size());
  for (std::size_t i = 0; i < loss.size(); ++i) iteration[i] = static_cast<double>(i + 1);
  if (Status s = WriteErrorPlot((folder / "plots/splat_loss.png").string(), iteration, loss,
                                ComputeStats(loss), "Splat training loss", "iteration", "loss (L1 + D-SSIM)");
      !s.ok())
    return s;
  return std::vector<std::string>{"plots/splat_loss.png"};
}

}  // namespace uf::pipeline
