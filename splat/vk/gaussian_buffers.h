// The model on the device, split into chunks of consecutive Gaussians so that no storage buffer exceeds
// maxStorageBufferRange (128 MiB on lavapipe; 1 M Gaussians of SH degree 3 are 192 MB of SH alone).
// Per chunk: geometry, 3 vec4 per Gaussian = (mu xyz, opacity logit), (log_scale xyz, 0), (q w x y z);
// SH, coefficient-major as in GaussianModel (3 (degree + 1)^2 floats per Gaussian).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "odometry/types/status.h"
#include "splat/gaussian_model.h"
#include "splat/vk/buffer.h"
#include "splat/vk/context.h"

namespace uf::splat::vk {

struct GaussianChunk {
  Buffer geometry, sh;
  std::uint32_t first = 0, count = 0;  // global index of the first Gaussian, Gaussians in the chunk
};

struct GaussianBuffers {
  std::vector<GaussianChunk> chunks;
  std::size_t count = 0;
  int sh_degree = 0;
};

// Gaussians per chunk: the most that keep both chunk buffers within the binding limit, or max_per_chunk
// when smaller and non-zero (tests use it to exercise several chunks on small models).
std::size_t GaussiansPerChunk(const Context& context, int sh_degree, std::size_t max_per_chunk);

// Uploads a valid model (the caller validates), reusing buffers that are large enough.
Status UploadGaussians(const Context& context, const GaussianModel& model, std::size_t max_per_chunk,
                       GaussianBuffers& buffers);

// Reads the model back from the device chunks (all memory is host-visible; after the frame that wrote it).
GaussianModel DownloadGaussians(const GaussianBuffers& buffers);

}  // namespace uf::splat::vk
