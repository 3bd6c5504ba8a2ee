#include "splat/vk/loss_pass.h"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "shaders/embedded_shaders.h"

namespace uf::splat::vk {

namespace {
constexpr int kBandRows = 16;  // rows per workgroup, kBandRows in shaders/photometric_loss.glsl
// Per band and subgroup slot (kMaxSubgroups, kPartialWords in shaders/photometric_loss.glsl): sum S,
// sum |r - t|, sum |E - d| / d (floats), depth pairs (uint).
constexpr std::size_t kSlotsPerBand = 16, kSlotWords = 4;

struct Push {
  std::int32_t width, height;
  float ssim_weight, depth_weight;
};

int Bands(int height) { return (height + kBandRows - 1) / kBandRows; }
}  // namespace

Expected<std::unique_ptr<LossPass>> LossPass::Create(const Context& context) {
  std::unique_ptr<LossPass> pass(new LossPass(context));
  struct Stage {
    std::unique_ptr<ComputePipeline>* pipeline;
    ShaderId id;
    std::uint32_t bindings;
    const char* name;
  };
  for (const Stage& stage :
       {Stage{&pass->moments_, ShaderId::kPhotometricLossMoments, 5, "photometric_loss_moments"},
        Stage{&pass->ssim_, ShaderId::kPhotometricLossSsim, 3, "photometric_loss_ssim"},
        Stage{&pass->partials_blur_, ShaderId::kPhotometricLossPartialsBlur, 2,
              "photometric_loss_partials_blur"},
        Stage{&pass->gradient_, ShaderId::kPhotometricLossGradient, 6, "photometric_loss_gradient"}}) {
    auto pipeline =
        ComputePipeline::Create(context, ShaderCode(stage.id), stage.bindings, sizeof(Push), stage.name);
    if (!pipeline.ok()) return pipeline.status();
    *stage.pipeline = std::move(pipeline.value());
  }
  return pass;
}

Status LossPass::Prepare(int width, int height) {
  if (width <= 0 || height <= 0)
    return Status::Error("photometric loss: image size must be positive, got " + std::to_string(width) +
                         " x " + std::to_string(height));
  const std::size_t pixels = static_cast<std::size_t>(width) * height, vec4 = 4 * sizeof(float);
  if (Status s = EnsureBuffer(context_, target_, pixels * vec4, "loss target"); !s.ok()) return s;
  if (Status s = EnsureBuffer(context_, moments_buffer_, pixels * 4 * vec4, "loss moments"); !s.ok())
    return s;
  if (Status s = EnsureBuffer(context_, ssim_partials_, pixels * 3 * vec4, "loss SSIM partials"); !s.ok())
    return s;
  if (Status s =
          EnsureBuffer(context_, band_sums_,
                       Bands(height) * kSlotsPerBand * kSlotWords * sizeof(std::uint32_t), "loss band sums");
      !s.ok())
    return s;
  width_ = width;
  height_ = height;
  return Status();
}

void LossPass::UploadTarget(const TrainingView& view) {
  const std::size_t pixels = static_cast<std::size_t>(width_) * height_;
  assert(view.rgb.size() == 3 * pixels && (view.depth.empty() || view.depth.size() == pixels));
  assert(view.mask.empty() || view.mask.size() == pixels);
  auto* out = static_cast<float*>(target_.data());
  for (std::size_t p = 0; p < pixels; ++p) {
    out[4 * p] = view.rgb[3 * p];
    out[4 * p + 1] = view.rgb[3 * p + 1];
    out[4 * p + 2] = view.rgb[3 * p + 2];
    // A depth <= 0 is no depth (as in the reference); only a masked pixel's is negative.
    out[4 * p + 3] = view.depth.empty() ? 0.0f : std::max(view.depth[p], 0.0f);
    if (!view.mask.empty() && view.mask[p] == 0) out[4 * p + 3] = kMaskedDepth;
  }
}

void LossPass::Record(FrameCommands& frame, const Buffer& colour, const Buffer& depth,
                      const Buffer& view_gradients, const PhotometricLossWeights& weights) const {
  [[maybe_unused]] const std::size_t pixels = static_cast<std::size_t>(width_) * height_;
  assert(pixels > 0 && colour.size() >= pixels * 16 && depth.size() >= pixels * 8 &&
         view_gradients.size() >= pixels * 32);
  recorded_weights_ = weights;
  const Push push{width_, height_, weights.ssim_weight, weights.depth_weight};
  const auto bands = static_cast<std::uint32_t>(Bands(height_));
  frame.Timestamp();
  frame.Fill(band_sums_, 0);  // the slots of subgroups that do not exist stay 0
  frame.Barrier();
  frame.Dispatch(*moments_, {&colour, &depth, &target_, &moments_buffer_, &band_sums_}, &push, bands);
  frame.Barrier();
  frame.Timestamp();
  frame.Dispatch(*ssim_, {&moments_buffer_, &ssim_partials_, &band_sums_}, &push, bands);
  frame.Barrier();
  frame.Timestamp();
  // The row blur of the partials reuses the moment buffer (its first 3 of 4 vec4 per pixel).
  frame.Dispatch(*partials_blur_, {&ssim_partials_, &moments_buffer_}, &push, bands);
  frame.Barrier();
  frame.Timestamp();
  frame.Dispatch(*gradient_, {&colour, &depth, &target_, &moments_buffer_, &band_sums_, &view_gradients},
                 &push, bands);
  frame.Barrier();
  frame.Timestamp();
}

PhotometricLossValue LossPass::ReadLoss() const {
  const std::size_t slots = Bands(height_) * kSlotsPerBand;
  std::vector<std::uint32_t> words(slots * kSlotWords);
  band_sums_.Download(words.data(), words.size() * sizeof(std::uint32_t));
  auto as_float = [](std::uint32_t bits) {
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return static_cast<double>(value);
  };
  double ssim_sum = 0, l1_sum = 0, depth_sum = 0;
  std::uint64_t pairs = 0;
  for (std::size_t slot = 0; slot < slots; ++slot) {
    ssim_sum += as_float(words[kSlotWords * slot]);
    l1_sum += as_float(words[kSlotWords * slot + 1]);
    depth_sum += as_float(words[kSlotWords * slot + 2]);
    pairs += words[kSlotWords * slot + 3];
  }
  const double n = 3.0 * width_ * static_cast<double>(height_), l = recorded_weights_.ssim_weight;
  PhotometricLossValue value;
  value.l1 = l1_sum / n;
  value.dssim = 1.0 - ssim_sum / n;
  value.depth = pairs > 0 ? depth_sum / static_cast<double>(pairs) : 0.0;
  value.total = (1 - l) * value.l1 + l * value.dssim + recorded_weights_.depth_weight * value.depth;
  return value;
}

}  // namespace uf::splat::vk
