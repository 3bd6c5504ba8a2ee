#include "viewer/pipeline/splat/splat_training.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

#include "splat/sky.h"
#include "splat/training/image_metrics.h"
#include "splat/training/scene_extent.h"

namespace uf::pipeline {

using Clock = std::chrono::steady_clock;

namespace {

// The training cameras' centres, T_world_camera's translations.
std::vector<Eigen::Vector3d> CameraCentres(const std::vector<StoredView>& views) {
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(views.size());
  for (const StoredView& v : views) centres.push_back(v.camera.T_world_camera.translation());
  return centres;
}

// Adds a step's device time per stage (ms) to the running sums (s), keeping the stages' order.
void AddStageTimes(const std::vector<std::pair<std::string, double>>& stage_ms,
                   std::vector<std::pair<std::string, double>>& sums) {
  for (const auto& [name, ms] : stage_ms) {
    auto sum = std::find_if(sums.begin(), sums.end(), [&](const auto& s) { return s.first == name; });
    if (sum == sums.end()) sum = sums.insert(sums.end(), {name, 0.0});
    sum->second += 1e-3 * ms;
  }
}

// The training views for each step: at the training size the stored views as they are; under coarse to fine
// (app::CoarseToFineSize) the views resized, made once per size (KITTI's 22 views at 621 x 187: 43 MB).
class CoarseToFineViews {
 public:
  CoarseToFineViews(const std::vector<StoredView>& train, const SplatConfig& config)
      : train_(train), config_(config) {}

  splat::TrainingView At(std::size_t k, int iteration) {
    const PinholeIntrinsics& full = train_.front().camera.pinhole;
    int width = 0, height = 0;
    app::CoarseToFineSize(config_, full.width, full.height, iteration, width, height);
    if (width == full.width && height == full.height) {
      resized_.clear();
      return ToTrainingView(train_[k]);
    }
    if (resized_.empty() || resized_.front().camera.pinhole.width != width) {
      resized_.clear();
      for (const StoredView& stored : train_)
        resized_.push_back(splat::ResizeView(ToTrainingView(stored), width, height));
    }
    return resized_[k];
  }

 private:
  const std::vector<StoredView>& train_;
  const SplatConfig& config_;
  std::vector<splat::TrainingView> resized_;
};

}  // namespace

void AddSky(splat::GaussianModel& model, const std::vector<StoredView>& train, const SplatConfig& config) {
  splat::AddSky(model, CameraCentres(train), config.sky_gaussians, config.training.prune_world_fraction);
}

Expected<SplatTrainingResult> TrainSplats(const splat::GaussianModel& seed,
                                          const std::vector<StoredView>& train,
                                          const std::vector<StoredView>& test, const SplatConfig& config,
                                          const std::string& device,
                                          const std::function<void(const TrainingProgress&)>& progress) {
  SplatTrainingResult result;
  result.scene_extent = splat::SceneExtent(CameraCentres(train));
  splat::SplatRendererOptions options;
  options.device = device;
  Expected<std::unique_ptr<splat::SplatTrainer>> trainer =
      splat::SplatTrainer::Create(seed, config.training, result.scene_extent, options);
  if (!trainer) return trainer.status();
  result.trainer = std::move(*trainer);
  if (!test.empty()) {
    Expected<SplatScores> initial = ScoreViews(*result.trainer, test);
    if (!initial) return initial.status();
    result.psnr_test_initial = initial->psnr;
  }

  // One pass over the training views per permutation; a new permutation for every pass.
  std::mt19937_64 random(config.training.seed);
  std::vector<std::size_t> order(train.size());
  std::size_t next = order.size();
  const int iterations = config.training.iterations;
  result.loss.reserve(static_cast<std::size_t>(iterations));
  const Clock::time_point start = Clock::now();
  result.exposures.assign(train.size(), splat::Exposure{});
  splat::ExposureFitOptions exposure_fit;
  exposure_fit.prior_weight = config.exposure_prior;
  std::vector<float> rendered;
  CoarseToFineViews views(train, config);
  for (int i = 0; i < iterations; ++i) {
    if (next == order.size()) {
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::shuffle(order.begin(), order.end(), random);
      next = 0;
    }
    const std::size_t k = order[next++];
    splat::TrainingView view = views.At(k, i);
    const bool fit_exposure = config.exposure_compensation && i >= config.exposure_from;
    const std::vector<float> image = fit_exposure ? view.rgb : std::vector<float>{};
    splat::RemoveExposure(result.exposures[k], view.rgb);
    Expected<splat::IterationStats> step = result.trainer->Step(view, fit_exposure ? &rendered : nullptr);
    if (fit_exposure && step)
      result.exposures[k] = splat::FitExposure(rendered, image, exposure_fit, view.mask);
    if (!step)
      return Status::Error("splat training, iteration " + std::to_string(i + 1) + ": " + step.error());
    result.loss.push_back(step->loss);
    result.iterations = i + 1;
    const double step_seconds = std::chrono::duration<double>(Clock::now() - start).count() - result.seconds;
    result.seconds += step_seconds;
    const int width = view.camera.pinhole.width, height = view.camera.pinhole.height;
    if (result.sizes.empty() || result.sizes.back().width != width || result.sizes.back().height != height)
      result.sizes.push_back({width, height});
    ++result.sizes.back().iterations;
    result.sizes.back().seconds += step_seconds;
    AddStageTimes(step->stage_ms, result.stage_seconds);
    if (progress) progress({i + 1, iterations, step->loss, step->gaussians, width, height});
    if (config.time_budget_s > 0 && result.seconds >= config.time_budget_s && i + 1 < iterations) {
      result.stopped_by_time = true;
      break;
    }
  }
  double device_seconds = 0;
  for (const auto& [name, seconds] : result.stage_seconds) device_seconds += seconds;
  result.stage_seconds.emplace_back("host", std::max(0.0, result.seconds - device_seconds));
  return result;
}

std::vector<splat::Exposure> ExposuresAt(const std::vector<StoredView>& views,
                                         const std::vector<StoredView>& train,
                                         const std::vector<splat::Exposure>& exposures) {
  if (exposures.empty()) return {};
  std::vector<Stamp> stamps;
  for (const StoredView& view : train) stamps.push_back(view.stamp);
  std::vector<splat::Exposure> at;
  for (const StoredView& view : views)
    at.push_back(splat::InterpolateExposure(stamps, exposures, view.stamp));
  return at;
}

Expected<SplatScores> ScoreViews(splat::SplatTrainer& trainer, const std::vector<StoredView>& views,
                                 const std::vector<splat::Exposure>& exposures,
                                 std::vector<splat::RenderedView>* renders, std::size_t keep) {
  SplatScores scores;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const StoredView& view = views[i];
    Expected<splat::RenderedView> rendered = trainer.Render(view.camera);
    if (!rendered) return rendered.status();
    if (i < exposures.size()) splat::ApplyExposure(exposures[i], rendered->rgb);
    const splat::TrainingView real = ToTrainingView(view);
    // The renderer's colours may leave [0, 1] (SH + 0.5, blending); the images are in [0, 1].
    std::vector<float> rgb = rendered->rgb;
    for (float& v : rgb) v = std::clamp(v, 0.0f, 1.0f);
    // Masked pixels are left out of PSNR and count as equal in SSIM's windows (as in the training loss).
    const std::span<const std::uint8_t> mask =
        view.mask ? std::span(*view.mask) : std::span<const std::uint8_t>();
    for (std::size_t p = 0; p < mask.size(); ++p)
      if (mask[p] == 0)
        for (int c = 0; c < 3; ++c) rgb[3 * p + c] = real.rgb[3 * p + c];
    const ViewScore score{view.stamp, splat::Psnr(rgb, real.rgb, mask),
                          splat::Ssim(rgb, real.rgb, view.camera.pinhole.width, view.camera.pinhole.height)};
    scores.views.push_back(score);
    scores.psnr += score.psnr / static_cast<double>(views.size());
    scores.ssim += score.ssim / static_cast<double>(views.size());
    if (renders && renders->size() < keep) renders->push_back(std::move(*rendered));
  }
  return scores;
}

std::vector<StoredView> SampleViews(const std::vector<StoredView>& views, std::size_t count) {
  if (views.size() <= count) return views;
  std::vector<StoredView> sample;
  for (std::size_t i = 0; i < count; ++i) sample.push_back(views[i * views.size() / count]);
  return sample;
}

}  // namespace uf::pipeline
