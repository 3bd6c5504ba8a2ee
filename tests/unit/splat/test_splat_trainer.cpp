// SplatTrainer (forward + loss + backward + Adam per submission, densification on the host): training from a
// perturbed copy of a scene brings its renders closer to the scene's own renders (the truth), the SH and
// densification schedules act at their iterations, an overflow of the key buffers does not apply a step
// twice, runs are deterministic, and bad input is rejected with the field named.
#include <gtest/gtest.h>

#include <random>

#include "splat/splat_renderer.h"
#include "splat/training/image_metrics.h"
#include "splat/training/splat_trainer.h"
#include "splat/views/training_images.h"
#include "tests/unit/splat/splat_test_support.h"

namespace uf::splat {
namespace {

using testing::Camera;
using testing::RandomScene;

constexpr int kWidth = 64, kHeight = 48;

SE3 ViewPose(int v) {
  return SE3(SO3::Exp(Eigen::Vector3d(0.05 * v, -0.1 * v, 0.02)), Eigen::Vector3d(0.2 * v, 0, 0));
}

// The truth's renders from 4 poses.
std::vector<TrainingView> TruthViews(const GaussianModel& truth) {
  Expected<std::unique_ptr<SplatRenderer>> renderer = SplatRenderer::Create();
  EXPECT_TRUE(renderer.ok()) << renderer.error();
  EXPECT_TRUE((*renderer)->Upload(truth).ok());
  std::vector<TrainingView> views;
  for (int v = 0; v < 4; ++v) {
    TrainingView view;
    view.camera = Camera(kWidth, kHeight, ViewPose(v));
    Expected<RenderedView> rendered = (*renderer)->Render(view.camera);
    EXPECT_TRUE(rendered.ok());
    view.rgb = rendered->rgb;
    views.push_back(std::move(view));
  }
  return views;
}

// The truth with its colours changed (SH DC + normal noise) and its opacities halved in logit.
GaussianModel Perturbed(GaussianModel model) {
  std::mt19937_64 rng(5);
  std::normal_distribution<float> normal(0.0f, 0.6f);
  for (std::size_t i = 0; i < model.size(); ++i) {
    for (int c = 0; c < 3; ++c) model.sh[i * model.ShStride() + c] += normal(rng);
    model.opacity_logits[i] *= 0.5f;
  }
  return model;
}

TrainingOptions NoDensification(int iterations) {
  TrainingOptions options;
  options.iterations = iterations;
  options.densify_from = options.densify_until = 0;
  options.opacity_reset_interval = 0;
  return options;
}

double MeanPsnr(SplatTrainer& trainer, const std::vector<TrainingView>& views) {
  double sum = 0;
  for (const TrainingView& view : views) {
    Expected<RenderedView> rendered = trainer.Render(view.camera);
    EXPECT_TRUE(rendered.ok());
    sum += Psnr(rendered->rgb, view.rgb);
  }
  return sum / static_cast<double>(views.size());
}

class SplatTrainerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    truth_ = RandomScene(41, 150, 0, Camera(kWidth, kHeight, SE3()));
    for (auto& q : truth_.rotations) q.normalize();
    views_ = TruthViews(truth_);
  }
  GaussianModel truth_;
  std::vector<TrainingView> views_;
};

TEST_F(SplatTrainerTest, TrainingMovesTheRendersTowardsTheTargetsAndIsDeterministic) {
  const int iterations = 80;
  auto trainer = SplatTrainer::Create(Perturbed(truth_), NoDensification(iterations), 2.0);
  ASSERT_TRUE(trainer.ok()) << trainer.error();
  const double before = MeanPsnr(**trainer, views_);
  double first_loss = 0, last_loss = 0;
  for (int it = 0; it < iterations; ++it) {
    Expected<IterationStats> stats = (*trainer)->Step(views_[it % views_.size()]);
    ASSERT_TRUE(stats.ok()) << stats.error();
    EXPECT_EQ(stats->iteration, it + 1);
    if (it < 4) first_loss += stats->loss;
    if (it >= iterations - 4) last_loss += stats->loss;
  }
  const double after = MeanPsnr(**trainer, views_);
  EXPECT_GT(after, before + 3.0) << "PSNR " << before << " -> " << after;
  EXPECT_LT(last_loss, 0.7 * first_loss);

  // The same run again: bit-identical (no atomics, seeded densification).
  auto again = SplatTrainer::Create(Perturbed(truth_), NoDensification(iterations), 2.0);
  ASSERT_TRUE(again.ok());
  for (int it = 0; it < iterations; ++it) ASSERT_TRUE((*again)->Step(views_[it % views_.size()]).ok());
  Expected<GaussianModel> a = (*trainer)->Model(), b = (*again)->Model();
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->positions, b->positions);
  EXPECT_EQ(a->sh, b->sh);
  EXPECT_EQ(a->opacity_logits, b->opacity_logits);
}

// Coarse to fine (viewer/pipeline/splat/splat_training.h): steps on the views at half size train the same
// model, and a full-size step after them sees no trace of the smaller frames: its loss equals that of a
// fresh trainer's first step from the same model.
TEST_F(SplatTrainerTest, StepsOnSmallerViewsTrainTheModelOfTheFullSize) {
  const int coarse_steps = 40;
  auto trainer = SplatTrainer::Create(Perturbed(truth_), NoDensification(100), 2.0);
  ASSERT_TRUE(trainer.ok()) << trainer.error();
  const double before = MeanPsnr(**trainer, views_);
  for (int it = 0; it < coarse_steps; ++it) {
    const TrainingView half = ResizeView(views_[it % views_.size()], kWidth / 2, kHeight / 2);
    ASSERT_TRUE((*trainer)->Step(half).ok());
  }
  const double after_coarse = MeanPsnr(**trainer, views_);
  EXPECT_GT(after_coarse, before + 2.0) << "PSNR at full size " << before << " -> " << after_coarse;

  Expected<GaussianModel> model = (*trainer)->Model();
  ASSERT_TRUE(model.ok());
  auto fresh = SplatTrainer::Create(*model, NoDensification(100), 2.0);  // SH degree 0 active in both
  ASSERT_TRUE(fresh.ok());
  Expected<IterationStats> next = (*trainer)->Step(views_[1]), first = (*fresh)->Step(views_[1]);
  ASSERT_TRUE(next.ok() && first.ok());
  EXPECT_NEAR(next->loss, first->loss, 1e-6);
  for (int it = 0; it < coarse_steps; ++it) ASSERT_TRUE((*trainer)->Step(views_[it % views_.size()]).ok());
  EXPECT_GT(MeanPsnr(**trainer, views_), after_coarse + 0.5);
}

TEST_F(SplatTrainerTest, ShBandsStayZeroUntilTheirDegreeIsActive) {
  TrainingOptions options = NoDensification(30);
  options.sh_degree = 2;
  options.sh_degree_interval = 10;
  auto trainer = SplatTrainer::Create(truth_, options, 2.0);
  ASSERT_TRUE(trainer.ok()) << trainer.error();
  auto band_energy = [&](int band) {
    Expected<GaussianModel> model = (*trainer)->Model();
    EXPECT_TRUE(model.ok());
    EXPECT_EQ(model->sh_degree, 2);
    double sum = 0;
    for (std::size_t i = 0; i < model->size(); ++i)
      for (int k = band * band; k < (band + 1) * (band + 1); ++k)
        for (int c = 0; c < 3; ++c) sum += std::abs(model->sh[i * model->ShStride() + 3 * k + c]);
    return sum;
  };
  for (int it = 1; it <= 30; ++it) {
    Expected<IterationStats> stats = (*trainer)->Step(views_[it % views_.size()]);
    ASSERT_TRUE(stats.ok());
    // The step's update uses the degree active before it: iteration / interval, counted after the step.
    EXPECT_EQ(stats->active_sh_degree, std::min(2, it / 10)) << it;
    if (it == 10) {
      EXPECT_EQ(band_energy(1), 0.0);
    }
    if (it == 11) {
      EXPECT_GT(band_energy(1), 0.0);
    }
    if (it == 20) {
      EXPECT_EQ(band_energy(2), 0.0);
    }
    if (it == 21) {
      EXPECT_GT(band_energy(2), 0.0);
    }
  }
}

TEST_F(SplatTrainerTest, DensificationAndOpacityResetRunOnTheirSchedule) {
  TrainingOptions options = NoDensification(40);
  options.densify_from = 10;
  options.densify_until = 30;
  options.densify_interval = 10;
  options.densify_gradient_threshold = 1e-7;  // every seen Gaussian qualifies
  options.opacity_reset_interval = 20;
  auto trainer = SplatTrainer::Create(Perturbed(truth_), options, 2.0);
  ASSERT_TRUE(trainer.ok()) << trainer.error();
  std::size_t gaussians = truth_.size();
  for (int it = 1; it <= 40; ++it) {
    Expected<IterationStats> stats = (*trainer)->Step(views_[it % views_.size()]);
    ASSERT_TRUE(stats.ok()) << stats.error();
    const bool scheduled = it == 10 || it == 20;  // 30 is densify_until (exclusive)
    EXPECT_EQ(stats->densified, scheduled) << it;
    if (scheduled) {
      EXPECT_GT(stats->cloned + stats->split, 0u) << it;
      EXPECT_EQ(stats->gaussians, gaussians + stats->cloned + stats->split - stats->pruned) << it;
    } else {
      EXPECT_EQ(stats->gaussians, gaussians) << it;
    }
    gaussians = stats->gaussians;
    if (it == 20) {  // opacity reset: every opacity <= 0.01
      Expected<GaussianModel> model = (*trainer)->Model();
      ASSERT_TRUE(model.ok());
      for (const float logit : model->opacity_logits) EXPECT_LE(logit, std::log(0.01f / 0.99f) + 1e-5f);
    }
  }
  Expected<GaussianModel> model = (*trainer)->Model();
  ASSERT_TRUE(model.ok());
  EXPECT_TRUE(model->Validate().ok());
  EXPECT_EQ(model->size(), gaussians);
}

TEST_F(SplatTrainerTest, NoOpacityResetInTheLastHalfIntervalOfTheRun) {
  // Reset every 20 iterations in a run of 25: the reset at 20 would leave 5 iterations to recover from it.
  TrainingOptions options = NoDensification(25);
  options.densify_until = 30;
  options.densify_from = 30;  // no densification (from = until), only the reset's schedule
  options.opacity_reset_interval = 20;
  auto trainer = SplatTrainer::Create(Perturbed(truth_), options, 2.0);
  ASSERT_TRUE(trainer.ok()) << trainer.error();
  for (int it = 1; it <= 25; ++it) {
    Expected<IterationStats> stats = (*trainer)->Step(views_[it % views_.size()]);
    ASSERT_TRUE(stats.ok()) << stats.error();
    EXPECT_FALSE(stats->densified) << it;
  }
}

// Large Gaussians touch many tiles: the first step's pairs overflow the initial key buffers (4096 slots
// for few Gaussians). The step must then be recorded again without applying Adam twice: the result equals a
// trainer whose buffers were already large (grown by a Render before its first step).
TEST_F(SplatTrainerTest, AKeyBufferOverflowDoesNotApplyAStepTwice) {
  GaussianModel big = truth_;
  for (auto& s : big.log_scales) s += Eigen::Vector3f::Constant(1.5f);
  TrainingView view = views_[0];
  view.camera = Camera(320, 240, ViewPose(0));
  view.rgb.assign(3 * 320 * 240, 0.5f);
  auto overflowing = SplatTrainer::Create(big, NoDensification(5), 2.0);
  auto grown = SplatTrainer::Create(big, NoDensification(5), 2.0);
  ASSERT_TRUE(overflowing.ok() && grown.ok());
  ASSERT_TRUE((*grown)->Render(view.camera).ok());
  ASSERT_TRUE((*overflowing)->Step(view).ok());
  ASSERT_TRUE((*grown)->Step(view).ok());
  Expected<GaussianModel> a = (*overflowing)->Model(), b = (*grown)->Model();
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->positions, b->positions);
  EXPECT_EQ(a->sh, b->sh);
  EXPECT_NE(a->positions, big.positions);  // a step was taken
}

TEST_F(SplatTrainerTest, RejectsBadInputNamingTheField) {
  TrainingOptions options;
  options.iterations = 0;
  auto bad_options = SplatTrainer::Create(truth_, options, 2.0);
  ASSERT_FALSE(bad_options.ok());
  EXPECT_NE(bad_options.error().find("iterations"), std::string::npos) << bad_options.error();
  EXPECT_FALSE(SplatTrainer::Create(truth_, TrainingOptions(), 0.0).ok());
  GaussianModel nan_model = truth_;
  nan_model.positions[3].x() = std::nanf("");
  auto nan = SplatTrainer::Create(nan_model, TrainingOptions(), 2.0);
  ASSERT_FALSE(nan.ok());
  EXPECT_NE(nan.error().find("3"), std::string::npos) << nan.error();
  EXPECT_FALSE(SplatTrainer::Create(GaussianModel(), TrainingOptions(), 2.0).ok());

  auto trainer = SplatTrainer::Create(truth_, TrainingOptions(), 2.0);
  ASSERT_TRUE(trainer.ok());
  TrainingView short_rgb = views_[0];
  short_rgb.rgb.pop_back();
  Expected<IterationStats> rejected = (*trainer)->Step(short_rgb);
  ASSERT_FALSE(rejected.ok());
  EXPECT_NE(rejected.error().find("rgb"), std::string::npos) << rejected.error();
  EXPECT_EQ((*trainer)->iteration(), 0);
}

}  // namespace
}  // namespace uf::splat
