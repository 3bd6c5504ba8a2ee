#include "splat/vk/gaussian_buffers.h"

#include <algorithm>

namespace uf::splat::vk {

namespace {
constexpr std::size_t kGeometryBytes = 3 * 4 * sizeof(float);
}

std::size_t GaussiansPerChunk(const Context& context, int sh_degree, std::size_t max_per_chunk) {
  const std::size_t limit = context.limits().maxStorageBufferRange;
  const std::size_t sh_bytes = 3 * ShCoefficientsPerChannel(sh_degree) * sizeof(float);
  std::size_t per_chunk = limit / std::max(kGeometryBytes, sh_bytes);
  if (max_per_chunk > 0) per_chunk = std::min(per_chunk, max_per_chunk);
  return std::max<std::size_t>(per_chunk, 1);
}

Status UploadGaussians(const Context& context, const GaussianModel& model, std::size_t max_per_chunk,
                       GaussianBuffers& buffers) {
  const std::size_t per_chunk = GaussiansPerChunk(context, model.sh_degree, max_per_chunk);
  const std::size_t num_chunks = (model.size() + per_chunk - 1) / per_chunk;
  const std::size_t stride = static_cast<std::size_t>(model.ShStride());
  buffers.chunks.resize(num_chunks);
  buffers.count = model.size();
  buffers.sh_degree = model.sh_degree;
  std::vector<float> geometry;
  for (std::size_t c = 0; c < num_chunks; ++c) {
    GaussianChunk& chunk = buffers.chunks[c];
    chunk.first = static_cast<std::uint32_t>(c * per_chunk);
    chunk.count = static_cast<std::uint32_t>(std::min(per_chunk, model.size() - chunk.first));
    const std::string name = "Gaussians chunk " + std::to_string(c);
    if (Status s = EnsureBuffer(context, chunk.geometry, chunk.count * kGeometryBytes, name + " geometry");
        !s.ok())
      return s;
    if (Status s = EnsureBuffer(context, chunk.sh, chunk.count * stride * sizeof(float), name + " SH");
        !s.ok())
      return s;
    geometry.assign(12 * static_cast<std::size_t>(chunk.count), 0.0f);
    for (std::uint32_t k = 0; k < chunk.count; ++k) {
      const std::size_t i = chunk.first + k;
      float* g = geometry.data() + 12 * k;
      for (int a = 0; a < 3; ++a) {
        g[a] = model.positions[i][a];
        g[4 + a] = model.log_scales[i][a];
      }
      g[3] = model.opacity_logits[i];
      const Eigen::Quaternionf& q = model.rotations[i];
      g[8] = q.w();
      g[9] = q.x();
      g[10] = q.y();
      g[11] = q.z();
    }
    chunk.geometry.Upload(geometry.data(), geometry.size() * sizeof(float));
    chunk.sh.Upload(model.sh.data() + chunk.first * stride, chunk.count * stride * sizeof(float));
  }
  return Status();
}

GaussianModel DownloadGaussians(const GaussianBuffers& buffers) {
  GaussianModel model;
  model.sh_degree = buffers.sh_degree;
  const std::size_t n = buffers.count, stride = static_cast<std::size_t>(model.ShStride());
  model.positions.resize(n);
  model.log_scales.resize(n);
  model.rotations.resize(n);
  model.opacity_logits.resize(n);
  model.sh.resize(n * stride);
  for (const GaussianChunk& chunk : buffers.chunks) {
    const auto* g = static_cast<const float*>(chunk.geometry.data());
    for (std::uint32_t k = 0; k < chunk.count; ++k, g += 12) {
      const std::size_t i = chunk.first + k;
      model.positions[i] = {g[0], g[1], g[2]};
      model.opacity_logits[i] = g[3];
      model.log_scales[i] = {g[4], g[5], g[6]};
      model.rotations[i] = Eigen::Quaternionf(g[8], g[9], g[10], g[11]);
    }
    chunk.sh.Download(model.sh.data() + chunk.first * stride, chunk.count * stride * sizeof(float));
  }
  return model;
}

}  // namespace uf::splat::vk
