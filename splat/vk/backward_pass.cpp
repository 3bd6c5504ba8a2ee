#include "splat/vk/backward_pass.h"

#include <algorithm>
#include <cassert>

#include "shaders/embedded_shaders.h"
#include "splat/vk/frame_params.h"

namespace uf::splat::vk {

namespace {
constexpr std::uint32_t kWorkgroup = 64;
constexpr std::size_t kGeometryGradientFloats = 16;  // 4 vec4 per Gaussian
// Push constants of rasterize_backward.comp (FrameParams' size, blend and background).
struct RasterizePush {
  std::int32_t size[4];
  float blend[4], background[4];
  std::uint32_t pages[4];  // slots per page, 0, 0, 0
};
}  // namespace

Expected<std::unique_ptr<BackwardPass>> BackwardPass::Create(const Context& context, std::size_t page_slots) {
  std::unique_ptr<BackwardPass> pass(new BackwardPass(context));
  const std::size_t limit_slots =
      context.limits().maxStorageBufferRange / (kPairGradientFloats * sizeof(float));
  pass->page_slots_ = static_cast<std::uint32_t>(
      std::min<std::size_t>(page_slots > 0 ? page_slots : limit_slots, limit_slots));
  auto rasterize = ComputePipeline::Create(context, ShaderCode(ShaderId::kRasterizeBackward), 10,
                                           sizeof(RasterizePush), "rasterize_backward");
  if (!rasterize.ok()) return rasterize.status();
  pass->rasterize_ = std::move(rasterize.value());
  auto project = ComputePipeline::Create(context, ShaderCode(ShaderId::kProjectBackward), 10,
                                         3 * sizeof(std::uint32_t), "project_backward");
  if (!project.ok()) return project.status();
  pass->project_ = std::move(project.value());
  return pass;
}

Status BackwardPass::Prepare(const ForwardState& forward) {
  const std::size_t pixels = static_cast<std::size_t>(forward.width) * forward.height;
  if (Status s = EnsureBuffer(context_, view_gradients_, std::max<std::size_t>(pixels, 1) * 8 * sizeof(float),
                              "view gradients");
      !s.ok())
    return s;
  const std::size_t pairs = std::max<std::size_t>(forward.pairs, 1);
  if (pairs > kPairPages * page_slots_)
    return Status::Error("splats: " + std::to_string(forward.pairs) +
                         " tile-Gaussian pairs in one view exceed the backward's " +
                         std::to_string(kPairPages * page_slots_) + " (" + std::to_string(kPairPages) +
                         " buffers within maxStorageBufferRange) on " + context_.device_name() +
                         ": train at a lower --resolution or with fewer Gaussians");
  for (std::size_t p = 0; p < kPairPages; ++p) {
    // Records [p S, (p + 1) S) of the frame, S = page_slots_; an unused page keeps one record.
    const std::size_t first = p * page_slots_;
    const std::size_t records = pairs > first ? std::min<std::size_t>(pairs - first, page_slots_) : 1;
    if (Status s = EnsureBuffer(context_, pair_pages_[p], records * kPairGradientFloats * sizeof(float),
                                "pair gradients, page " + std::to_string(p) + " (" +
                                    std::to_string(forward.pairs) + " tile-Gaussian pairs)");
        !s.ok())
      return s;
  }
  const GaussianBuffers& gaussians = *forward.gaussians;
  const std::size_t stride = 3 * static_cast<std::size_t>(ShCoefficientsPerChannel(gaussians.sh_degree));
  chunks_.resize(gaussians.chunks.size());
  sh_floats_written_.resize(chunks_.size());
  for (std::size_t c = 0; c < chunks_.size(); ++c) {
    const void* previous_sh = chunks_[c].sh.data();
    const std::size_t count = std::max<std::uint32_t>(gaussians.chunks[c].count, 1);
    const std::string name = "gradients of chunk " + std::to_string(c);
    if (Status s = EnsureBuffer(context_, chunks_[c].geometry,
                                count * kGeometryGradientFloats * sizeof(float), name + " geometry");
        !s.ok())
      return s;
    if (Status s = EnsureBuffer(context_, chunks_[c].sh, count * stride * sizeof(float), name + " SH");
        !s.ok())
      return s;
    // A new buffer or another model stride: contents unknown.
    if (chunks_[c].sh.data() != previous_sh || stride != sh_stride_) sh_floats_written_[c] = ~0u;
  }
  sh_stride_ = stride;
  return Status();
}

void BackwardPass::UploadViewGradients(const ViewGradients& gradients, std::size_t pixels) {
  assert(gradients.rgb.size() == 3 * pixels);
  assert(gradients.alpha.empty() || gradients.alpha.size() == pixels);
  assert(gradients.depth_sum.empty() || gradients.depth_sum.size() == pixels);
  auto* out = static_cast<float*>(view_gradients_.data());
  for (std::size_t p = 0; p < pixels; ++p) {
    float* g = out + 8 * p;
    g[0] = gradients.rgb[3 * p];
    g[1] = gradients.rgb[3 * p + 1];
    g[2] = gradients.rgb[3 * p + 2];
    g[3] = gradients.alpha.empty() ? 0.0f : gradients.alpha[p];
    g[4] = gradients.depth_sum.empty() ? 0.0f : gradients.depth_sum[p];
    g[5] = g[6] = g[7] = 0.0f;
  }
}

void BackwardPass::Record(FrameCommands& frame, const ForwardState& forward) const {
  // The frame parameters rasterize_backward needs, pushed (its bindings are the buffers below); the
  // forward's Prepare wrote them to the host-visible parameter buffer before this frame was recorded.
  const auto& params = *static_cast<const FrameParams*>(forward.params->data());
  RasterizePush push{};
  std::copy_n(params.size, 4, push.size);
  std::copy_n(params.blend, 4, push.blend);
  std::copy_n(params.background, 4, push.background);
  push.pages[0] = page_slots_;
  // Stage 2 writes the SH gradients up to the active degree only; those above it must be zero: zero-filled
  // (before the barrier after stage 1) when an earlier frame may have written them.
  const std::vector<GaussianChunk>& chunks = forward.gaussians->chunks;
  const std::uint32_t active = params.counts[3];
  const std::uint32_t active_floats = 3 * (active + 1) * (active + 1);
  frame.Timestamp();
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    if (sh_floats_written_[c] > active_floats) frame.Fill(chunks_[c].sh, 0);
    sh_floats_written_[c] = active_floats;
  }
  // 1. Per tile: dL/d(images) -> one gradient record per tile-Gaussian pair (every slot written once).
  frame.Dispatch(*rasterize_,
                 {forward.tile_ranges, forward.sorted_ids, forward.projected, forward.rects, forward.offsets,
                  &view_gradients_, forward.pixel_state, &pair_pages_[0], &pair_pages_[1], &pair_pages_[2]},
                 &push, static_cast<std::uint32_t>(forward.tiles_x),
                 static_cast<std::uint32_t>(forward.tiles_y));
  frame.Barrier();
  frame.Timestamp();
  // 2. Per Gaussian, chunk by chunk: sum of its pair records -> model parameters.
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    const std::uint32_t push[3] = {chunks[c].first, chunks[c].count, page_slots_};
    frame.Dispatch(*project_,
                   {forward.params, &chunks[c].geometry, &chunks[c].sh, forward.rects, forward.offsets,
                    &pair_pages_[0], &chunks_[c].geometry, &chunks_[c].sh, &pair_pages_[1], &pair_pages_[2]},
                   push, (chunks[c].count + kWorkgroup - 1) / kWorkgroup);
  }
  frame.Barrier();
  frame.Timestamp();
}

void BackwardPass::Download(const ForwardState& forward, GaussianGradients* out) const {
  const GaussianBuffers& gaussians = *forward.gaussians;
  const std::size_t n = gaussians.count;
  const std::size_t stride = 3 * static_cast<std::size_t>(ShCoefficientsPerChannel(gaussians.sh_degree));
  out->position.resize(n);
  out->log_scale.resize(n);
  out->rotation.resize(n);
  out->opacity_logit.resize(n);
  out->sh.resize(n * stride);
  out->mean_2d.resize(n);
  for (std::size_t c = 0; c < gaussians.chunks.size(); ++c) {
    const GaussianChunk& chunk = gaussians.chunks[c];
    const auto* g = static_cast<const float*>(chunks_[c].geometry.data());
    for (std::uint32_t k = 0; k < chunk.count; ++k, g += kGeometryGradientFloats) {
      const std::size_t i = chunk.first + k;
      out->position[i] = {g[0], g[1], g[2]};
      out->opacity_logit[i] = g[3];
      out->log_scale[i] = {g[4], g[5], g[6]};
      out->rotation[i] = {g[8], g[9], g[10], g[11]};
      out->mean_2d[i] = {g[12], g[13]};
    }
    chunks_[c].sh.Download(out->sh.data() + chunk.first * stride, chunk.count * stride * sizeof(float));
  }
}

}  // namespace uf::splat::vk
