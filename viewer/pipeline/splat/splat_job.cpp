#include "viewer/pipeline/splat/splat_job.h"

#include <algorithm>

#include "odometry/io/dataset_reader.h"
#include "viewer/pipeline/run/run_record.h"
#include "viewer/pipeline/splat/feature_seeds.h"
#include "viewer/pipeline/splat/splat_run_inputs.h"
#include "viewer/pipeline/splat/splat_training.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kTrainViewsScored = 16;

void Progress(const SplatJobCallbacks& callbacks, const std::string& phase, std::int64_t done,
              std::int64_t total, const std::string& unit) {
  if (callbacks.progress) callbacks.progress(phase, done, total, unit);
}

// "12.3k" for progress lines.
std::string Count(std::size_t n) {
  char text[32];
  if (n >= 10000)
    std::snprintf(text, sizeof(text), "%.1fk", n / 1000.0);
  else
    std::snprintf(text, sizeof(text), "%zu", n);
  return text;
}

}  // namespace

Expected<SplatJobResult> RunSplatJob(const fs::path& run_dir, const SplatJobOptions& options,
                                     const SplatJobCallbacks& callbacks) {
  const SplatConfig& config = options.config;
  if (Status s = config.Validate(); !s.ok()) return Status::Error("splat: " + s.message());
  Expected<pipeline::RunRecord> record = pipeline::ReadRunRecord(run_dir);
  if (!record) return record.status();
  const pipeline::RunFrames& frames = record->frames;
  Expected<DatasetConfig> dataset_config = RunDatasetConfig(run_dir);
  if (!dataset_config) return dataset_config.status();
  Expected<std::unique_ptr<DatasetReader>> reader = OpenDataset(record->dataset, dataset_config->reader);
  if (!reader) return reader.status();
  Expected<MeasurementStream> stream = MeasurementStream::Create(**reader, dataset_config->stream);
  if (!stream) return stream.status();
  const DatasetDescription& description = stream->description();
  Expected<SplatCameraStream> camera = FindSplatCamera(description, frames.T_output_body);
  if (!camera) return camera.status();
  Expected<Trajectory> trajectory =
      ReadSplatTrajectory(options.poses.empty() ? run_dir / "trajectory.tum" : fs::path(options.poses));
  if (!trajectory) return trajectory.status();

  Expected<splat::SeedResult> seeded = SeedFromRunMap(run_dir, config.training.sh_degree, config.seed_points);
  if (!seeded) return seeded.status();
  if (seeded->uncoloured > 0 && callbacks.warning)
    callbacks.warning(std::to_string(seeded->uncoloured) + " of " + std::to_string(seeded->map_points) +
                      " map points have no colour: their Gaussians start grey");

  ViewLoading loading;
  loading.trajectory = &*trajectory;
  loading.T_map_world = frames.T_map_world;
  loading.config = &config;
  if (config.training.depth_weight > 0) loading.depth_points = seeded->model.positions;
  Expected<SplatViews> views = LoadSplatViews(*stream, *camera, loading, [&](std::int64_t images) {
    Progress(callbacks, "images", images, 0, "images");
  });
  if (!views) return views.status();
  const std::int64_t selected = static_cast<std::int64_t>(views->train.size() + views->test.size());
  if (views->test.empty())
    return Status::Error("camera " + views->camera_name + ": " + std::to_string(views->images) + " images, " +
                         std::to_string(views->outside_trajectory) + " outside the trajectory's time span, " +
                         std::to_string(selected) +
                         " selected as keyframes: at least 3 are needed (two to train on, one held " +
                         "out between them); nothing trained");

  const std::size_t map_seeds = seeded->model.size();
  FeatureSeedStats feature_seeds;
  if (config.feature_seed_corners > 0) {
    FeatureSeedOptions seed_options;
    seed_options.max_features = config.feature_seed_corners;
    Expected<FeatureSeedStats> added = AddFeatureSeeds(seeded->model, map_seeds, views->train, seed_options);
    if (!added) return added.status();
    feature_seeds = *added;
  }
  AddSky(seeded->model, views->train, config);

  const int planned = config.training.iterations;
  Expected<SplatTrainingResult> trained = TrainSplats(
      seeded->model, views->train, views->test, config, options.device, [&](const TrainingProgress& p) {
        char unit[128];
        std::snprintf(unit, sizeof(unit), "iterations, loss %.4f, %s Gaussians, %d x %d px", p.loss,
                      Count(p.gaussians).c_str(), p.width, p.height);
        Progress(callbacks, "train", p.iteration, planned, unit);
      });
  if (!trained) return trained.status();
  splat::SplatTrainer& trainer = *trained->trainer;

  SplatJobResult result;
  SplatMetrics& m = result.metrics;
  std::vector<splat::RenderedView> renders;
  const std::vector<splat::Exposure> test_exposures =
      ExposuresAt(views->test, views->train, trained->exposures);
  Expected<SplatScores> test = ScoreViews(trainer, views->test, test_exposures, &renders,
                                          static_cast<std::size_t>(config.comparisons));
  if (!test) return test.status();
  const std::vector<StoredView> train_sample = SampleViews(views->train, kTrainViewsScored);
  Expected<SplatScores> train =
      ScoreViews(trainer, train_sample, ExposuresAt(train_sample, views->train, trained->exposures));
  if (!train) return train.status();
  Expected<splat::GaussianModel> model = trainer.Model();
  if (!model) return model.status();

  m.test = *test, m.train = *train;
  m.psnr_test_initial = trained->psnr_test_initial;
  m.iterations = trained->iterations, m.iterations_planned = planned;
  m.seconds = trained->seconds;
  m.stage_seconds = trained->stage_seconds;
  m.sizes = trained->sizes;
  m.stopped_by_time = trained->stopped_by_time;
  m.gaussians = model->size(), m.gaussians_initial = seeded->model.size();
  m.map_seeds = map_seeds, m.feature_seeds = feature_seeds.added;
  m.sky_gaussians = seeded->model.size() - map_seeds - feature_seeds.added;
  m.uncoloured_seeds = seeded->uncoloured, m.unseen_map_points = seeded->unseen_left_out;
  m.device = trainer.device_name(), m.camera = views->camera_name;
  m.width = views->pinhole.width, m.height = views->pinhole.height;
  m.views_train = views->train.size(), m.views_test = views->test.size();
  m.images = views->images, m.images_outside_trajectory = views->outside_trajectory;
  m.images_undecodable = views->undecodable;
  m.masked_pixels = views->masked_pixels;
  m.scene_extent_m = trained->scene_extent;
  m.sh_degree = config.training.sh_degree;
  m.exposure_compensation = config.exposure_compensation;
  if (config.exposure_compensation) {
    for (std::size_t i = 0; i < views->train.size(); ++i)
      m.exposures.push_back({views->train[i].stamp, false, trained->exposures[i]});
    for (std::size_t i = 0; i < views->test.size(); ++i)
      m.exposures.push_back({views->test[i].stamp, true, test_exposures[i]});
    std::sort(m.exposures.begin(), m.exposures.end(),
              [](const ViewExposure& a, const ViewExposure& b) { return a.stamp < b.stamp; });
  }

  // Outputs, each atomic; metrics.json last (its presence says the rest is there).
  Expected<std::vector<std::string>> splats = WriteSplatFiles(run_dir, *model);
  if (!splats) return splats.status();
  result.files = *splats;
  Expected<std::vector<std::string>> comparisons = WriteComparisons(run_dir, views->test, renders);
  if (!comparisons) return comparisons.status();
  result.files.insert(result.files.end(), comparisons->begin(), comparisons->end());
  Expected<std::vector<std::string>> plot = WriteLossPlot(run_dir, trained->loss);
  if (!plot) return plot.status();
  result.files.insert(result.files.end(), plot->begin(), plot->end());
  if (Status s = WriteSplatMetrics(run_dir / "metrics.json", m); !s.ok()) return s;
  result.files.push_back("metrics.json");
  result.test = std::move(views->test);
  result.model = views->model;
  return result;
}

}  // namespace uf::pipeline
