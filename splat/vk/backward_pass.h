// The backward pass of the splat renderer on Vulkan compute: dL/d(rendered images) -> dL/d(model
// parameters), recorded into a frame's command buffer after the forward (so that a training iteration can be
// one submission: forward + loss + backward + optimizer). Two shaders: rasterize_backward.comp (per tile,
// back to front, one gradient record per tile-Gaussian pair) and project_backward.comp (per Gaussian: sums
// its pair records and chains them through the projection, SH and sigmoid). No float atomics: the gradients
// are deterministic. Internal to splat/ (includes vulkan.h through the buffers).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "odometry/types/status.h"
#include "splat/cpu_reference/reference_backward.h"
#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/context.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/gaussian_buffers.h"

namespace uf::splat::vk {

// What the backward reads of the forward frame (the renderer's buffers after its frame ran).
struct ForwardState {
  const Buffer* params = nullptr;       // FrameParams
  const Buffer* tile_ranges = nullptr;  // per tile [begin, end) in the sorted pairs
  const Buffer* sorted_ids = nullptr;   // Gaussian index per sorted pair
  const Buffer* projected = nullptr;    // 3 vec4 per Gaussian
  const Buffer* rects = nullptr;        // touched tiles per Gaussian
  const Buffer* offsets = nullptr;      // first pair slot per Gaussian
  const GaussianBuffers* gaussians = nullptr;
  int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
  const Buffer* pixel_state = nullptr;  // per pixel: what the forward's blending ended with
  std::size_t pairs = 0;  // tile-Gaussian pair slots of the frame (the key capacity, >= the pairs)
};

// Gradient buffers of one model chunk: geometry 4 vec4 per Gaussian = (dL/dmu, dL/dopacity_logit),
// (dL/dlog_scale, 0), (dL/dq w x y z), (dL/d(u, v) summed over pixels, 0, 0); SH like the model's SH.
struct GradientChunk {
  Buffer geometry, sh;
};

class BackwardPass {
 public:
  static constexpr std::size_t kPairGradientFloats = 12;  // 3 vec4, see shaders/rasterize_backward.comp
  // The pair records of a frame (48 bytes per tile-Gaussian pair) are split over this many buffers ("pages"),
  // since one buffer is bound whole and each must stay under the device's maxStorageBufferRange: 128 MiB on
  // lavapipe, 2.8 M pairs, which a 1242 x 375 training view passed at ~430k Gaussians.
  static constexpr std::size_t kPairPages = 3;

  // page_slots: pair records per page; 0 (the default): as many as the device's binding limit allows (a
  // test sets fewer, to cross the page boundary with a small frame).
  static Expected<std::unique_ptr<BackwardPass>> Create(const Context& context, std::size_t page_slots = 0);

  // Sizes the view-gradient, pair and output buffers for this frame. Errors: a buffer over the device's
  // binding limit, or more pairs than the pages hold.
  Status Prepare(const ForwardState& forward);
  // dL/d(images) into the view-gradient buffer (2 vec4 per pixel: (dL/drgb, dL/dalpha), (dL/dD, 0, 0, 0)).
  // A loss shader may write that buffer instead (view_gradients()).
  void UploadViewGradients(const ViewGradients& gradients, std::size_t pixels);
  // Records both stages (with the barriers between and after them) into the open frame, with timestamps
  // before, between and after them (3). Reads the frame parameters the forward's Prepare wrote (pushed; its
  // active SH degree: the SH gradients above it are zero).
  void Record(FrameCommands& frame, const ForwardState& forward) const;
  // Reads the gradients back after the frame ran (sizes `out` for `count` Gaussians of `sh_degree`).
  void Download(const ForwardState& forward, GaussianGradients* out) const;

  const Buffer& view_gradients() const { return view_gradients_; }
  const std::vector<GradientChunk>& chunks() const { return chunks_; }

 private:
  BackwardPass(const Context& context) : context_(context) {}
  const Context& context_;
  std::unique_ptr<ComputePipeline> rasterize_, project_;
  Buffer view_gradients_;
  std::array<Buffer, kPairPages> pair_pages_;
  std::uint32_t page_slots_ = 0;
  std::vector<GradientChunk> chunks_;
  // Per chunk: SH floats per Gaussian (from the first) that may be nonzero in its SH gradient buffer; the
  // rest are zero. The shader writes only the active ones; Record zero-fills when this exceeds them.
  mutable std::vector<std::uint32_t> sh_floats_written_;
  std::size_t sh_stride_ = 0;
};

}  // namespace uf::splat::vk
