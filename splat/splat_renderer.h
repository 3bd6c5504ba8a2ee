// SplatRenderer: renders a GaussianModel with Vulkan compute (shaders/*.comp), headless, on a GPU or on
// Mesa's lavapipe CPU device. A frame is one command buffer: projection (EWA + SH), prefix sum of tile
// counts, tile-key emission, stable radix sort of (tile, depth) keys, tile ranges, tile rasterization.
// Results follow the rules in splat/render_types.h; splat/cpu_reference is the reference they are tested
// against. Vulkan stays out of this header.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "odometry/types/status.h"
#include "splat/cpu_reference/reference_backward.h"
#include "splat/gaussian_model.h"
#include "splat/render_types.h"

namespace uf::splat {

struct SplatRendererOptions {
  // Vulkan device: "" picks a discrete GPU, else an integrated GPU, else the CPU device (lavapipe); a number
  // is an index into ListSplatDevices(); other text is a case-insensitive substring of the device name.
  std::string device;
  // Upper bound on Gaussians per device buffer chunk; 0: as many as the 128 MiB binding limit allows.
  std::size_t max_gaussians_per_chunk = 0;
};

// What the last frame did (the benchmark divides pixel_gaussian_pairs by the rasterization time).
struct SplatFrameStats {
  std::size_t gaussians = 0;               // in the model
  std::size_t visible_gaussians = 0;       // touching at least one tile
  std::size_t tile_gaussian_pairs = 0;     // keys sorted
  std::uint64_t pixel_gaussian_pairs = 0;  // alpha evaluations in the rasterizer
  int submissions = 0;                     // 1, or 2 when the key buffers had to grow
  // Device time per stage of the last submission (timestamp queries), e.g. {"project", 1.2}; empty when the
  // queue has no timestamps.
  std::vector<std::pair<std::string, double>> stage_ms;
};

// "0: llvmpipe (LLVM 15.0.6, 256 bits) (CPU)" per device, or an error saying what to install.
Expected<std::vector<std::string>> ListSplatDevices();

// The name of the device that SplatRendererOptions::device `device` (not empty) picks, without creating
// anything on it: a cheap check of a user's choice before long work. Errors: no Vulkan driver (what to
// install), no device of that index or name (the devices present).
Expected<std::string> FindSplatDevice(const std::string& device);

class SplatRenderer {
 public:
  static Expected<std::unique_ptr<SplatRenderer>> Create(const SplatRendererOptions& options = {});
  ~SplatRenderer();
  SplatRenderer(const SplatRenderer&) = delete;
  SplatRenderer& operator=(const SplatRenderer&) = delete;

  // Validates and uploads the model; it stays on the device until the next Upload.
  Status Upload(const GaussianModel& model);
  // Renders the uploaded model (an empty model gives the background). Errors: invalid camera or settings,
  // buffers over the device limits, Vulkan failures.
  Expected<RenderedView> Render(const SplatCamera& camera, const RenderSettings& settings = {});
  // Gradients of a loss L with respect to the uploaded model's parameters given dL/d(images) of the last
  // Render (its device state is reused), with the meaning and layout of RenderReferenceBackward; adds the
  // stages "rasterize backward" and "project backward" to last_frame_stats().stage_ms. Errors: no
  // Render since the last Upload, image gradients of the wrong size, buffers over the device limits, Vulkan.
  Expected<GaussianGradients> Backward(const ViewGradients& dL_dview);

  const std::string& device_name() const;
  const SplatFrameStats& last_frame_stats() const;

 private:
  struct Impl;
  explicit SplatRenderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::splat
