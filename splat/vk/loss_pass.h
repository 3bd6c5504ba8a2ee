// The photometric training loss on Vulkan compute (L = (1 - l) L1 + l (1 - SSIM) + w_d L_depth, the CPU
// specification is EvaluatePhotometricLoss in splat/cpu_reference/photometric_loss.h), recorded into a frame
// opened by its user between the forward and the backward: it reads the forward's colour and depth images
// and the target view, and writes the backward's whole view-gradient buffer. Four shaders
// (shaders/photometric_loss_*.comp), one workgroup per band of 16 rows each: row blur of the 5 SSIM moment
// images, column blur + SSIM map + its 3 partial maps, row blur of the partials, column blur + gradient. The
// loss terms come from per-band, per-subgroup partial sums that the host adds in double (no float atomics:
// deterministic). Internal to splat/ (includes vulkan.h through the buffers).
#pragma once

#include <memory>

#include "odometry/types/status.h"
#include "splat/cpu_reference/photometric_loss.h"
#include "splat/training/training_options.h"
#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/context.h"
#include "splat/vk/frame_commands.h"

namespace uf::splat::vk {

class LossPass {
 public:
  static constexpr int kStageCount = 4;  // dispatches (each with a barrier and a timestamp) Record adds
  static constexpr const char* kStageNames[kStageCount] = {"loss moments", "loss ssim", "loss partials blur",
                                                           "loss gradient"};

  static Expected<std::unique_ptr<LossPass>> Create(const Context& context);

  // Sizes the target (vec4 per pixel: rgb, depth), moment (15 floats per pixel), partial-map (9 floats per
  // pixel) and partial-sum buffers for this image size. Errors: a size that is not positive, a buffer over
  // the device's binding limit.
  Status Prepare(int width, int height);
  // Target depth of a masked pixel (TrainingView::mask): the shaders take the target's rgb as the rendered
  // value there and give it no gradient.
  static constexpr float kMaskedDepth = -1.0f;
  // Writes the view's rgb (and depth; 0 where it has none, kMaskedDepth where masked) into the host-visible
  // target buffer. The view must have the prepared size (asserted).
  void UploadTarget(const TrainingView& view);
  // Records the four stages (each followed by a barrier) into the open frame, with a timestamp before the
  // first and after each (kStageCount + 1). colour: vec4 per pixel (rgb
  // with background, alpha); depth: 2 floats per pixel (median, expected depth; expected = inf where alpha <
  // 1e-4); view_gradients: at least 2 vec4 per pixel, written whole ((dL/drgb, dL/dalpha), (dL/dD, 0, 0, 0)).
  void Record(FrameCommands& frame, const Buffer& colour, const Buffer& depth, const Buffer& view_gradients,
              const PhotometricLossWeights& weights) const;
  // After the frame ran: the loss terms (the partial sums added in double) with the weights of the last
  // Record.
  PhotometricLossValue ReadLoss() const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  explicit LossPass(const Context& context) : context_(context) {}
  const Context& context_;
  std::unique_ptr<ComputePipeline> moments_, ssim_, partials_blur_, gradient_;
  Buffer target_, moments_buffer_, ssim_partials_, band_sums_;
  int width_ = 0, height_ = 0;
  mutable PhotometricLossWeights recorded_weights_;  // what ReadLoss weights the terms with
};

}  // namespace uf::splat::vk
