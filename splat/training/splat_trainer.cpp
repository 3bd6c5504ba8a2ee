#include "splat/training/splat_trainer.h"

#include <algorithm>

#include "splat/cpu_reference/photometric_loss.h"
#include "splat/cpu_reference/reference_renderer.h"
#include "splat/training/densify.h"
#include "splat/training/learning_rate.h"
#include "splat/vk/adam_pass.h"
#include "splat/vk/backward_pass.h"
#include "splat/vk/context.h"
#include "splat/vk/forward_pass.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/gaussian_buffers.h"
#include "splat/vk/loss_pass.h"

namespace uf::splat {

struct SplatTrainer::Impl {
  TrainingOptions options;
  double scene_extent = 1;
  std::size_t max_per_chunk = 0;
  std::unique_ptr<vk::Context> context;
  std::unique_ptr<vk::FrameCommands> frame;
  std::unique_ptr<vk::ForwardPass> forward;
  std::unique_ptr<vk::LossPass> loss;
  std::unique_ptr<vk::BackwardPass> backward;
  std::unique_ptr<vk::AdamPass> adam;
  vk::GaussianBuffers gaussians;
  int iteration = 0;

  int ActiveShDegree() const { return std::min(options.sh_degree, iteration / options.sh_degree_interval); }
  AdamStep MakeAdamStep(int width, int height) const;
  // Forward + loss + backward + Adam in one submission; false when the key buffers overflowed (the Adam
  // shader then left the model untouched, and the step must be recorded again).
  Expected<bool> Submit(const TrainingView& view, const FloatCamera& camera, IterationStats* stats);
  Status Densify(IterationStats* stats);
};

namespace {

Status CheckView(const TrainingView& view) {
  if (Status s = view.camera.Validate(); !s.ok())
    return Status::Error("training view camera: " + s.message());
  const PinholeIntrinsics& pinhole = view.camera.pinhole;
  const std::size_t pixels = static_cast<std::size_t>(pinhole.width) * pinhole.height;
  if (view.rgb.size() != 3 * pixels)
    return Status::Error("training view: rgb has " + std::to_string(view.rgb.size()) + " values, expected " +
                         std::to_string(3 * pixels) + " (3 x " + std::to_string(pinhole.width) + " x " +
                         std::to_string(pinhole.height) + ")");
  if (!view.depth.empty() && view.depth.size() != pixels)
    return Status::Error("training view: depth has " + std::to_string(view.depth.size()) +
                         " values, expected " + std::to_string(pixels) + " (or none)");
  if (!view.mask.empty() && view.mask.size() != pixels)
    return Status::Error("training view: mask has " + std::to_string(view.mask.size()) +
                         " values, expected " + std::to_string(pixels) + " (or none)");
  return Status();
}

}  // namespace

Expected<std::unique_ptr<SplatTrainer>> SplatTrainer::Create(const GaussianModel& initial,
                                                             const TrainingOptions& options,
                                                             double scene_extent,
                                                             const SplatRendererOptions& device) {
  if (Status s = options.Validate(); !s.ok()) return Status::Error("splat training: " + s.message());
  if (!(scene_extent >= 1e-3 && std::isfinite(scene_extent)))
    return Status::Error("splat training: scene extent must be >= 1e-3 m, got " +
                         std::to_string(scene_extent));
  if (Status s = initial.Validate("initial splats"); !s.ok()) return s;
  if (initial.size() == 0) return Status::Error("splat training: the initial model has no Gaussians");
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->scene_extent = scene_extent;
  impl->max_per_chunk = device.max_gaussians_per_chunk;
  Expected<std::unique_ptr<vk::Context>> context = vk::Context::Create({device.device});
  if (!context.ok()) return context.status();
  impl->context = std::move(context.value());
  const vk::Context& c = *impl->context;
  auto frame = vk::FrameCommands::Create(c, 512, 24);
  if (!frame.ok()) return frame.status();
  impl->frame = std::move(frame.value());
  auto forward = vk::ForwardPass::Create(c);
  if (!forward.ok()) return forward.status();
  impl->forward = std::move(forward.value());
  auto loss = vk::LossPass::Create(c);
  if (!loss.ok()) return loss.status();
  impl->loss = std::move(loss.value());
  auto backward = vk::BackwardPass::Create(c);
  if (!backward.ok()) return backward.status();
  impl->backward = std::move(backward.value());
  auto adam = vk::AdamPass::Create(c, impl->max_per_chunk);
  if (!adam.ok()) return adam.status();
  impl->adam = std::move(adam.value());

  // The model at the final SH degree (higher bands zero; Adam keeps the inactive bands at zero).
  GaussianModel model = initial;
  if (model.sh_degree != options.sh_degree) model = WithShDegree(model, options.sh_degree);
  if (Status s = vk::UploadGaussians(c, model, impl->max_per_chunk, impl->gaussians); !s.ok()) return s;
  if (Status s = impl->adam->Prepare(impl->gaussians); !s.ok()) return s;
  return std::unique_ptr<SplatTrainer>(new SplatTrainer(std::move(impl)));
}

SplatTrainer::SplatTrainer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SplatTrainer::~SplatTrainer() = default;

int SplatTrainer::iteration() const { return impl_->iteration; }
const std::string& SplatTrainer::device_name() const { return impl_->context->device_name(); }

AdamStep SplatTrainer::Impl::MakeAdamStep(int width, int height) const {
  const TrainingOptions& o = options;
  AdamStep step{};
  step.lr_position = static_cast<float>(PositionLearningRate(o, iteration, scene_extent));
  step.lr_log_scale = static_cast<float>(o.lr_log_scale);
  step.lr_rotation = static_cast<float>(o.lr_rotation);
  step.lr_opacity = static_cast<float>(o.lr_opacity);
  step.lr_sh_dc = static_cast<float>(o.lr_sh_dc);
  step.lr_sh_rest = static_cast<float>(o.lr_sh_rest);
  step.beta1 = static_cast<float>(o.adam_beta1);
  step.beta2 = static_cast<float>(o.adam_beta2);
  step.epsilon = static_cast<float>(o.adam_epsilon);
  step.step = iteration + 1;
  step.active_sh_coefficients = ShCoefficientsPerChannel(ActiveShDegree());
  // 3DGS measures the screen-space gradient in normalized device coordinates: u_ndc = 2 u / W - 1, so
  // dL/du_ndc = dL/du * W / 2.
  step.ndc_scale_x = 0.5f * static_cast<float>(width);
  step.ndc_scale_y = 0.5f * static_cast<float>(height);
  return step;
}

Expected<bool> SplatTrainer::Impl::Submit(const TrainingView& view, const FloatCamera& camera,
                                          IterationStats* stats) {
  if (Status s = forward->Prepare(gaussians, camera, options.render, ActiveShDegree()); !s.ok()) return s;
  if (Status s = loss->Prepare(camera.width, camera.height); !s.ok()) return s;
  loss->UploadTarget(view);
  if (Status s = adam->Prepare(gaussians); !s.ok()) return s;
  if (Status s = frame->Begin(); !s.ok()) return s;
  forward->Record(*frame, gaussians);
  const vk::ForwardState state = forward->State(gaussians);
  if (Status s = backward->Prepare(state); !s.ok()) return s;
  const PhotometricLossWeights weights{static_cast<float>(options.ssim_weight),
                                       static_cast<float>(options.depth_weight)};
  loss->Record(*frame, forward->colour(), forward->depth(), backward->view_gradients(), weights);
  backward->Record(*frame, state);
  adam->Record(*frame, gaussians, backward->chunks(), forward->tile_counts(),
               MakeAdamStep(camera.width, camera.height), state.projected,
               {&forward->counters(), forward->pair_capacity()});
  frame->Timestamp();
  if (Status s = frame->SubmitAndWait(); !s.ok()) return s;
  SplatFrameStats frame_stats;
  if (!forward->Finish(&frame_stats)) return false;
  const std::vector<double> intervals = frame->IntervalsMs();
  // The intervals between the frame's timestamps, in recording order; nullptr: the empty gap between two
  // passes (one ends and the next begins with a timestamp).
  std::vector<const char*> names(std::begin(vk::ForwardPass::kStageNames),
                                 std::end(vk::ForwardPass::kStageNames));
  names.push_back(nullptr);
  names.insert(names.end(), std::begin(vk::LossPass::kStageNames), std::end(vk::LossPass::kStageNames));
  for (const char* name :
       {static_cast<const char*>(nullptr), "rasterize backward", "project backward", "adam"})
    names.push_back(name);
  for (std::size_t i = 0; i < intervals.size() && i < names.size(); ++i)
    if (names[i] != nullptr) stats->stage_ms.emplace_back(names[i], intervals[i]);
  const PhotometricLossValue value = loss->ReadLoss();
  stats->loss = value.total;
  stats->l1 = value.l1;
  stats->dssim = value.dssim;
  stats->depth = value.depth;
  return true;
}

Expected<IterationStats> SplatTrainer::Step(const TrainingView& view, std::vector<float>* rendered_rgb) {
  if (Status s = CheckView(view); !s.ok()) return s;
  Impl& m = *impl_;
  const FloatCamera camera = MakeFloatCamera(view.camera);
  IterationStats stats;
  bool done = false;
  for (int attempt = 0; attempt < 2 && !done; ++attempt) {
    Expected<bool> submitted = m.Submit(view, camera, &stats);
    if (!submitted.ok()) return submitted.status();
    done = submitted.value();
  }
  if (!done) return Status::Error("splat training: key buffers did not grow");
  if (rendered_rgb) {
    RenderedView rendered;
    m.forward->ReadView(&rendered);
    *rendered_rgb = std::move(rendered.rgb);
  }
  ++m.iteration;
  stats.iteration = m.iteration;
  stats.active_sh_degree = m.ActiveShDegree();
  if (Status s = m.Densify(&stats); !s.ok()) return s;
  stats.gaussians = m.gaussians.count;
  return stats;
}

// Densification, pruning and opacity reset on the schedule of TrainingOptions, on the host (all memory is
// host-visible on lavapipe; on a GPU this round trip costs a few ms every densify_interval iterations).
Status SplatTrainer::Impl::Densify(IterationStats* stats) {
  const TrainingOptions& o = options;
  const bool densify =
      iteration >= o.densify_from && iteration < o.densify_until && iteration % o.densify_interval == 0;
  // A reset leaves the model nearly transparent and the opacities need iterations to come back: none in
  // the run's last half interval (a run of 1000 would end on one, with an almost black model).
  const bool reset = o.opacity_reset_interval > 0 && iteration % o.opacity_reset_interval == 0 &&
                     iteration < o.densify_until && iteration + o.opacity_reset_interval / 2 <= o.iterations;
  if (!densify && !reset) return Status();
  Expected<OptimizerHostState> state = adam->Download(gaussians);
  if (!state.ok()) return state.status();
  if (densify) {
    const DensifyResult result =
        DensifyAndPrune(*state, o, scene_extent, o.seed ^ static_cast<std::uint64_t>(iteration));
    stats->cloned = result.cloned;
    stats->split = result.split;
    stats->pruned = result.pruned;
  }
  if (reset) ResetOpacity(*state);
  stats->densified = true;
  return adam->Upload(*state, *context, gaussians);
}

Expected<GaussianModel> SplatTrainer::Model() const {
  // The model alone (the optimizer's moments and statistics stay on the device).
  return vk::DownloadGaussians(impl_->gaussians);
}

Expected<RenderedView> SplatTrainer::Render(const SplatCamera& camera) {
  if (Status s = camera.Validate(); !s.ok()) return Status::Error("camera: " + s.message());
  Impl& m = *impl_;
  const FloatCamera float_camera = MakeFloatCamera(camera);
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (Status s = m.forward->Prepare(m.gaussians, float_camera, m.options.render, m.ActiveShDegree());
        !s.ok())
      return s;
    if (Status s = m.frame->Begin(); !s.ok()) return s;
    m.forward->Record(*m.frame, m.gaussians);
    if (Status s = m.frame->SubmitAndWait(); !s.ok()) return s;
    SplatFrameStats stats;
    if (m.forward->Finish(&stats)) {
      RenderedView view;
      m.forward->ReadView(&view);
      return view;
    }
  }
  return Status::Error("splat training: key buffers did not grow");
}

}  // namespace uf::splat
