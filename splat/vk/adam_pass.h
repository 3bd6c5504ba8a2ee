// The Adam optimizer of splat training on Vulkan compute (shaders/adam_step.comp), recorded into an open
// frame after the backward pass (vk/backward_pass.h), so that a training iteration stays one submission.
// Holds, per model chunk, Adam's moments (m, v) of the geometry (3 vec4 per Gaussian, the model geometry's
// layout) and of the SH (like the model's SH), and the 3DGS densification statistics (3 x 32 bits per
// Gaussian: gradient accumulator, view count, max screen radius). The host round trip for densification
// (Download / Upload) goes through OptimizerHostState. Internal to splat/ (includes vulkan.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "odometry/types/status.h"
#include "splat/training/optimizer_state.h"
#include "splat/vk/backward_pass.h"
#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/context.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/gaussian_buffers.h"

namespace uf::splat::vk {

// The forward's pair count and key capacity: the step is skipped on the device when the pairs overflowed
// the keys (see shaders/adam_step.comp).
struct ForwardCheck {
  const Buffer* counters = nullptr;  // the forward's counters; null: no check
  std::uint32_t pair_capacity = 0;
};

class AdamPass {
 public:
  // max_gaussians_per_chunk: the chunking Upload gives the model (as SplatRendererOptions; 0: the device's).
  static Expected<std::unique_ptr<AdamPass>> Create(const Context& context,
                                                    std::size_t max_gaussians_per_chunk = 0);

  // Sizes the moment and statistics buffers for the model's chunks. A chunk whose range of Gaussians and SH
  // degree are unchanged since the last Prepare / Upload keeps its contents; any other starts at zero.
  Status Prepare(const GaussianBuffers& model);
  // Records one step over every chunk (one dispatch per chunk, then a barrier) into the open frame.
  // gradients: the backward's chunks (same chunking as model); tile_counts: uint per Gaussian (global
  // index), > 0 when seen this frame; projected: the forward's projected Gaussians (3 vec4 per Gaussian,
  // global index, radius in px at .w of the second), or null (max radius then stays as it is).
  void Record(FrameCommands& frame, GaussianBuffers& model, const std::vector<GradientChunk>& gradients,
              const Buffer& tile_counts, const AdamStep& step, const Buffer* projected = nullptr,
              const ForwardCheck& check = {}) const;

  // The model, the moments and the statistics in host arrays (after the frames that wrote them ran).
  Expected<OptimizerHostState> Download(const GaussianBuffers& model) const;
  // Writes `state` (Consistent()) to the device: the model into `model` (re-chunked and resized when the
  // count changed) and the moments and statistics into this pass's buffers.
  Status Upload(const OptimizerHostState& state, const Context& context, GaussianBuffers& model);

 private:
  struct ChunkState {
    Buffer m_geometry, v_geometry, m_sh, v_sh, statistics;
    std::uint32_t first = 0, count = 0;
    int sh_degree = -1;
  };
  AdamPass(const Context& context, std::size_t max_per_chunk)
      : context_(context), max_per_chunk_(max_per_chunk) {}
  const Context& context_;
  std::size_t max_per_chunk_ = 0;
  std::unique_ptr<ComputePipeline> pipeline_;
  std::vector<ChunkState> chunks_;
};

}  // namespace uf::splat::vk
