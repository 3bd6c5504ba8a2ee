#include "splat/vk/adam_pass.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <string>

#include "shaders/embedded_shaders.h"

namespace uf::splat::vk {

namespace {

constexpr std::uint32_t kWorkgroup = 256;
constexpr std::uint32_t kMaxGroups = 256;            // grid-stride loops cover the rest
constexpr std::size_t kStatisticsWords = 3;          // accumulator, count, max radius per Gaussian
constexpr std::size_t kGeometryGradientFloats = 16;  // 4 vec4 per Gaussian (backward_pass.h)

// Mirrors the push constants of shaders/adam_step.comp.
struct AdamPush {
  std::uint32_t sh_vec4s, count, base, sh_stride, active_floats, sh_scalars, has_projected;
  float beta1, beta2, epsilon, c1, c2;
  float lr_position, lr_log_scale, lr_rotation, lr_opacity, lr_sh_dc, lr_sh_rest;
  float ndc_scale_x, ndc_scale_y;
  std::uint32_t pair_capacity;
};
static_assert(sizeof(AdamPush) == 84);

std::uint32_t Groups(std::uint32_t invocations) {
  return std::clamp<std::uint32_t>((invocations + kWorkgroup - 1) / kWorkgroup, 1, kMaxGroups);
}

}  // namespace

Expected<std::unique_ptr<AdamPass>> AdamPass::Create(const Context& context,
                                                     std::size_t max_gaussians_per_chunk) {
  std::unique_ptr<AdamPass> pass(new AdamPass(context, max_gaussians_per_chunk));
  auto pipeline =
      ComputePipeline::Create(context, ShaderCode(ShaderId::kAdamStep), 12, sizeof(AdamPush), "adam_step");
  if (!pipeline.ok()) return pipeline.status();
  pass->pipeline_ = std::move(pipeline.value());
  return pass;
}

Status AdamPass::Prepare(const GaussianBuffers& model) {
  const std::size_t stride = 3 * static_cast<std::size_t>(ShCoefficientsPerChannel(model.sh_degree));
  chunks_.resize(model.chunks.size());
  for (std::size_t c = 0; c < chunks_.size(); ++c) {
    const GaussianChunk& chunk = model.chunks[c];
    ChunkState& state = chunks_[c];
    if (state.first == chunk.first && state.count == chunk.count && state.sh_degree == model.sh_degree)
      continue;  // unchanged: keep the moments and statistics
    const std::size_t count = std::max<std::uint32_t>(chunk.count, 1);
    const std::string name = "Adam state of chunk " + std::to_string(c);
    struct Sized {
      Buffer* buffer;
      std::size_t bytes;
      const char* what;
    };
    for (const Sized& b :
         {Sized{&state.m_geometry, count * kGeometryMomentFloats * sizeof(float), " m geometry"},
          Sized{&state.v_geometry, count * kGeometryMomentFloats * sizeof(float), " v geometry"},
          Sized{&state.m_sh, count * stride * sizeof(float), " m SH"},
          Sized{&state.v_sh, count * stride * sizeof(float), " v SH"},
          Sized{&state.statistics, count * kStatisticsWords * sizeof(std::uint32_t), " statistics"}}) {
      if (Status s = EnsureBuffer(context_, *b.buffer, b.bytes, name + b.what); !s.ok()) return s;
      std::memset(b.buffer->data(), 0, b.bytes);
    }
    state.first = chunk.first;
    state.count = chunk.count;
    state.sh_degree = model.sh_degree;
  }
  return Status();
}

void AdamPass::Record(FrameCommands& frame, GaussianBuffers& model,
                      const std::vector<GradientChunk>& gradients, const Buffer& tile_counts,
                      const AdamStep& step, const Buffer* projected, const ForwardCheck& check) const {
  assert(gradients.size() >= model.chunks.size() && chunks_.size() == model.chunks.size());
  assert(step.step >= 1 && step.active_sh_coefficients >= 1);
  const std::uint32_t stride = 3 * static_cast<std::uint32_t>(ShCoefficientsPerChannel(model.sh_degree));
  AdamPush push{};
  push.sh_stride = stride;
  push.active_floats = 3 * static_cast<std::uint32_t>(step.active_sh_coefficients);
  // The shader's two SH loops (vec4 when the stride allows, else float by float): one runs, one has 0 trips.
  push.sh_vec4s = stride % 4 == 0 ? (push.active_floats + 3) / 4 : 0;
  push.sh_scalars = stride % 4 == 0 ? 0 : push.active_floats;
  push.has_projected = projected != nullptr ? 1 : 0;
  push.beta1 = step.beta1;
  push.beta2 = step.beta2;
  push.epsilon = step.epsilon;
  push.c1 = AdamBiasCorrection(step.beta1, step.step);
  push.c2 = AdamBiasCorrection(step.beta2, step.step);
  push.lr_position = step.lr_position;
  push.lr_log_scale = step.lr_log_scale;
  push.lr_rotation = step.lr_rotation;
  push.lr_opacity = step.lr_opacity;
  push.lr_sh_dc = step.lr_sh_dc;
  push.lr_sh_rest = step.lr_sh_rest;
  push.ndc_scale_x = step.ndc_scale_x;
  push.ndc_scale_y = step.ndc_scale_y;
  const Buffer* radii = projected != nullptr ? projected : &tile_counts;  // bound but unread without it
  // Without a check the shader compares tile_counts[0] with the largest capacity: always passes.
  push.pair_capacity = check.counters != nullptr ? check.pair_capacity : 0xffffffffu;
  const Buffer* counters = check.counters != nullptr ? check.counters : &tile_counts;
  for (std::size_t c = 0; c < model.chunks.size(); ++c) {
    GaussianChunk& chunk = model.chunks[c];
    const ChunkState& state = chunks_[c];
    assert(state.first == chunk.first && state.count == chunk.count);
    if (chunk.count == 0) continue;
    push.base = chunk.first;
    push.count = chunk.count;
    frame.Dispatch(
        *pipeline_,
        {&chunk.geometry, &state.m_geometry, &state.v_geometry, &gradients[c].geometry, &chunk.sh,
         &state.m_sh, &state.v_sh, &gradients[c].sh, &tile_counts, &state.statistics, radii, counters},
        &push, Groups(push.count));
  }
  frame.Barrier();
}

Expected<OptimizerHostState> AdamPass::Download(const GaussianBuffers& model) const {
  if (chunks_.size() != model.chunks.size())
    return Status::Error("Adam state: " + std::to_string(chunks_.size()) + " chunks, the model has " +
                         std::to_string(model.chunks.size()) + " (Prepare or Upload first)");
  OptimizerHostState state;
  state.model = DownloadGaussians(model);
  state.ResizeToModel();
  const std::size_t stride = static_cast<std::size_t>(state.model.ShStride());
  for (std::size_t c = 0; c < chunks_.size(); ++c) {
    const ChunkState& chunk = chunks_[c];
    if (chunk.first != model.chunks[c].first || chunk.count != model.chunks[c].count ||
        chunk.sh_degree != model.sh_degree)
      return Status::Error("Adam state: chunk " + std::to_string(c) + " does not match the model's");
    const std::size_t first = chunk.first, count = chunk.count;
    const std::size_t geometry_bytes = count * kGeometryMomentFloats * sizeof(float);
    chunk.m_geometry.Download(state.m_geometry.data() + first * kGeometryMomentFloats, geometry_bytes);
    chunk.v_geometry.Download(state.v_geometry.data() + first * kGeometryMomentFloats, geometry_bytes);
    chunk.m_sh.Download(state.m_sh.data() + first * stride, count * stride * sizeof(float));
    chunk.v_sh.Download(state.v_sh.data() + first * stride, count * stride * sizeof(float));
    const auto* words = static_cast<const std::uint32_t*>(chunk.statistics.data());
    for (std::size_t k = 0; k < count; ++k) {
      std::memcpy(&state.gradient_accum[first + k], &words[kStatisticsWords * k], sizeof(float));
      state.gradient_count[first + k] = words[kStatisticsWords * k + 1];
      std::memcpy(&state.max_radius[first + k], &words[kStatisticsWords * k + 2], sizeof(float));
    }
  }
  return state;
}

Status AdamPass::Upload(const OptimizerHostState& state, const Context& context, GaussianBuffers& model) {
  assert(state.Consistent());
  assert(&context == &context_);
  if (Status s = UploadGaussians(context, state.model, max_per_chunk_, model); !s.ok()) return s;
  for (ChunkState& chunk : chunks_) chunk.sh_degree = -1;  // re-sized (buffers reused when large enough)
  if (Status s = Prepare(model); !s.ok()) return s;
  const std::size_t stride = static_cast<std::size_t>(state.model.ShStride());
  for (std::size_t c = 0; c < chunks_.size(); ++c) {
    ChunkState& chunk = chunks_[c];
    const std::size_t first = chunk.first, count = chunk.count;
    const std::size_t geometry_bytes = count * kGeometryMomentFloats * sizeof(float);
    chunk.m_geometry.Upload(state.m_geometry.data() + first * kGeometryMomentFloats, geometry_bytes);
    chunk.v_geometry.Upload(state.v_geometry.data() + first * kGeometryMomentFloats, geometry_bytes);
    chunk.m_sh.Upload(state.m_sh.data() + first * stride, count * stride * sizeof(float));
    chunk.v_sh.Upload(state.v_sh.data() + first * stride, count * stride * sizeof(float));
    auto* words = static_cast<std::uint32_t*>(chunk.statistics.data());
    for (std::size_t k = 0; k < count; ++k) {
      std::memcpy(&words[kStatisticsWords * k], &state.gradient_accum[first + k], sizeof(float));
      words[kStatisticsWords * k + 1] = state.gradient_count[first + k];
      std::memcpy(&words[kStatisticsWords * k + 2], &state.max_radius[first + k], sizeof(float));
    }
  }
  return Status();
}

}  // namespace uf::splat::vk
