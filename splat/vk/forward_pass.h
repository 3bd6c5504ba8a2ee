// The forward pass of the splat renderer on Vulkan compute, recorded into a frame opened by its user (the
// renderer submits it alone, the trainer follows it with loss, backward and optimizer in the same
// submission): projection (EWA + SH), prefix sum of tile counts, tile-key emission, stable radix sort of
// (tile, depth) keys, tile ranges, tile rasterization. Its buffers are what the backward pass reads.
// Internal to splat/ (includes vulkan.h through the buffers).
#pragma once

#include <cstdint>
#include <memory>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/render_types.h"
#include "splat/splat_renderer.h"
#include "splat/vk/backward_pass.h"
#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/gaussian_buffers.h"

namespace uf::splat::vk {

class ForwardPass {
 public:
  static constexpr std::uint32_t kStageCount = 6;  // timestamps intervals Record adds (kStageNames)
  static constexpr const char* kStageNames[kStageCount] = {"project", "scan",        "emit keys",
                                                           "sort",    "tile ranges", "rasterize"};

  static Expected<std::unique_ptr<ForwardPass>> Create(const Context& context);

  // Sizes the frame buffers for the model and camera and writes the frame parameters. active_sh_degree: the
  // SH bands evaluated by this frame and its backward (bands above it count as zero and get zero
  // gradients; the trainer's active degree); < 0: the model's degree. Errors: buffers over the device limits.
  Status Prepare(const GaussianBuffers& gaussians, const FloatCamera& camera, const RenderSettings& settings,
                 int active_sh_degree = -1);
  // Records the frame's dispatches (with a timestamp before and after each stage) into the open frame; the
  // last dispatch is followed by a barrier.
  void Record(FrameCommands& frame, const GaussianBuffers& gaussians);
  // After the frame ran: the counts of the frame into `stats` (gaussians, visible, pairs, pixel pairs).
  // Returns false when the tile-Gaussian pairs overflowed the key buffers: the capacity has then grown and
  // the frame must be prepared and recorded again (its images and everything computed from them are invalid).
  bool Finish(SplatFrameStats* stats);

  // The images of the last frame.
  void ReadView(RenderedView* view) const;
  // What the backward pass reads of the last frame.
  ForwardState State(const GaussianBuffers& gaussians) const;

  const Buffer& colour() const { return colour_; }            // vec4 per pixel: rgb (with background), alpha
  const Buffer& depth() const { return depth_; }              // 2 floats per pixel: median, expected depth
  const Buffer& tile_counts() const { return tile_counts_; }  // uint per Gaussian: tiles touched (0: unseen)
  const Buffer& counters() const { return counters_; }        // [0] pairs, [1] visible, [2..3] pixel pairs
  std::uint32_t pair_capacity() const { return static_cast<std::uint32_t>(pair_capacity_); }

 private:
  explicit ForwardPass(const Context& context) : context_(context) {}
  const Context& context_;
  std::unique_ptr<ComputePipeline> project_, emit_, prefix_sum_, histogram_, scatter_, ranges_, rasterize_;
  std::uint32_t sort_lanes_ = 256;
  FloatCamera camera_{};
  std::size_t pair_capacity_ = 0;
  int sorted_ = -1;  // which key/value buffer pair holds the sorted result of the last frame
  Buffer params_, counters_, projected_, rects_, tile_counts_, offsets_, lane_sums_, histogram_counts_,
      histogram_scanned_, tile_ranges_, colour_, depth_, pixel_state_;
  Buffer keys_[2], values_[2];
};

}  // namespace uf::splat::vk
