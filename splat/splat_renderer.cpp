#include "splat/splat_renderer.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "shaders/embedded_shaders.h"
#include "splat/cpu_reference/reference_renderer.h"
#include "splat/vk/backward_pass.h"
#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/context.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/frame_params.h"
#include "splat/vk/gaussian_buffers.h"
#include "splat/vk/gpu_primitives.h"

namespace uf::splat {

namespace {

constexpr std::uint32_t kWorkgroup = 64;
constexpr std::uint32_t kCounters = 8;  // see shaders/frame_params.glsl (0..3) and gpu_primitives.cpp (4)
constexpr std::size_t kProjectedBytes = 3 * 4 * sizeof(float);
constexpr const char* kStageNames[] = {"project", "scan", "emit keys", "sort", "tile ranges", "rasterize"};

std::uint32_t Groups(std::size_t n) { return static_cast<std::uint32_t>((n + kWorkgroup - 1) / kWorkgroup); }

}  // namespace

struct SplatRenderer::Impl {
  std::unique_ptr<vk::Context> context;
  std::unique_ptr<vk::ComputePipeline> project, emit, prefix_sum, histogram, scatter, ranges, rasterize;
  std::unique_ptr<vk::FrameCommands> frame;
  std::size_t max_per_chunk = 0;
  std::uint32_t sort_lanes = 256;
  vk::GaussianBuffers gaussians;
  // Frame buffers, kept between frames and grown when needed.
  vk::Buffer params, counters, projected, rects, tile_counts, offsets, lane_sums, histogram_counts,
      histogram_scanned, tile_ranges, colour, depth;
  vk::Buffer keys[2], values[2];
  std::size_t pair_capacity = 0;
  SplatFrameStats stats;
  // Backward pass (created on first use) and what it needs of the last frame (sorted < 0: none).
  std::unique_ptr<vk::BackwardPass> backward;
  int last_sorted = -1;
  FloatCamera last_camera{};

  Status EnsureFrameBuffers(std::size_t n, const FloatCamera& camera);
  Status Record(const FloatCamera& camera, int* sorted);
  void ReadStats(int* sorted);
};

Expected<std::vector<std::string>> ListSplatDevices() {
  Expected<std::vector<vk::DeviceInfo>> devices = vk::ListDevices();
  if (!devices.ok()) return devices.status();
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < devices->size(); ++i)
    lines.push_back(std::to_string(i) + ": " + (*devices)[i].name + " (" + (*devices)[i].type + ")");
  return lines;
}

Status ValidateRenderSettings(const RenderSettings& s) {
  auto error = [](const std::string& field, const std::string& rule, float value) {
    return Status::Error("render settings: " + field + " must be " + rule + ", got " + std::to_string(value));
  };
  if (!(std::isfinite(s.near) && s.near > 0)) return error("near", "positive and finite", s.near);
  if (!(s.low_pass >= 0 && std::isfinite(s.low_pass)))
    return error("low_pass", ">= 0 and finite", s.low_pass);
  if (!(s.max_alpha > 0 && s.max_alpha <= 1)) return error("max_alpha", "in (0, 1]", s.max_alpha);
  if (!(s.min_alpha >= 0 && s.min_alpha < s.max_alpha))
    return error("min_alpha", "in [0, max_alpha)", s.min_alpha);
  if (!(s.transmittance_cutoff >= 0 && s.transmittance_cutoff < 1))
    return error("transmittance_cutoff", "in [0, 1)", s.transmittance_cutoff);
  if (!s.background.allFinite()) return error("background", "finite", s.background.norm());
  return Status();
}

Expected<std::unique_ptr<SplatRenderer>> SplatRenderer::Create(const SplatRendererOptions& options) {
  auto impl = std::make_unique<Impl>();
  Expected<std::unique_ptr<vk::Context>> context = vk::Context::Create({options.device});
  if (!context.ok()) return context.status();
  impl->context = std::move(context.value());
  impl->max_per_chunk = options.max_gaussians_per_chunk;
  // Radix-sort lanes (each sorts a contiguous chunk serially): a few per CPU core on lavapipe, many on a GPU.
  impl->sort_lanes = impl->context->is_cpu() ? 256 : 8192;

  using vk::ShaderId;
  const struct {
    std::unique_ptr<vk::ComputePipeline>* pipeline;
    ShaderId id;
    std::uint32_t bindings, push_bytes;
    const char* name;
  } pipelines[] = {
      {&impl->project, ShaderId::kProjectGaussians, 7, 8, "project_gaussians"},
      {&impl->emit, ShaderId::kEmitTileKeys, 6, 0, "emit_tile_keys"},
      {&impl->prefix_sum, ShaderId::kPrefixSum, 4, 12, "prefix_sum"},
      {&impl->histogram, ShaderId::kRadixHistogram, 3, 16, "radix_histogram"},
      {&impl->scatter, ShaderId::kRadixScatter, 6, 16, "radix_scatter"},
      {&impl->ranges, ShaderId::kTileRanges, 3, 8, "tile_ranges"},
      {&impl->rasterize, ShaderId::kRasterizeForward, 7, 0, "rasterize_forward"},
  };
  for (const auto& p : pipelines) {
    auto created =
        vk::ComputePipeline::Create(*impl->context, vk::ShaderCode(p.id), p.bindings, p.push_bytes, p.name);
    if (!created.ok()) return created.status();
    *p.pipeline = std::move(created.value());
  }
  Expected<std::unique_ptr<vk::FrameCommands>> frame = vk::FrameCommands::Create(*impl->context, 256, 8);
  if (!frame.ok()) return frame.status();
  impl->frame = std::move(frame.value());
  return std::unique_ptr<SplatRenderer>(new SplatRenderer(std::move(impl)));
}

SplatRenderer::SplatRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SplatRenderer::~SplatRenderer() = default;

const std::string& SplatRenderer::device_name() const { return impl_->context->device_name(); }
const SplatFrameStats& SplatRenderer::last_frame_stats() const { return impl_->stats; }

Status SplatRenderer::Upload(const GaussianModel& model) {
  if (Status s = model.Validate(); !s.ok()) return s;
  // The projected records of all Gaussians sit in one buffer, bound whole.
  const std::size_t limit = impl_->context->limits().maxStorageBufferRange;
  if (model.size() * kProjectedBytes > limit)
    return Status::Error("splats: " + std::to_string(model.size()) +
                         " Gaussians exceed the renderer's limit of " +
                         std::to_string(limit / kProjectedBytes) + " on " + device_name());
  impl_->last_sorted = -1;
  return vk::UploadGaussians(*impl_->context, model, impl_->max_per_chunk, impl_->gaussians);
}

Status SplatRenderer::Impl::EnsureFrameBuffers(std::size_t n, const FloatCamera& camera) {
  const vk::Context& c = *context;
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  const std::size_t tiles = static_cast<std::size_t>(camera.tiles_x) * camera.tiles_y;
  if (pair_capacity == 0) pair_capacity = std::max<std::size_t>(4096, 4 * n);
  const std::size_t histogram_bytes = 256 * sizeof(std::uint32_t) * sort_lanes;
  for (const auto& [buffer, bytes, name] : {
           std::tuple{&params, sizeof(vk::FrameParams), "frame parameters"},
           {&counters, kCounters * sizeof(std::uint32_t), "counters"},
           {&projected, n * kProjectedBytes, "projected Gaussians"},
           {&rects, n * 4 * sizeof(std::int32_t), "tile rectangles"},
           {&tile_counts, n * sizeof(std::uint32_t), "tile counts"},
           {&offsets, n * sizeof(std::uint32_t), "key offsets"},
           {&lane_sums, vk::kScanLanes * sizeof(std::uint32_t), "prefix-sum scratch"},
           {&histogram_counts, histogram_bytes, "radix histogram"},
           {&histogram_scanned, histogram_bytes, "radix histogram (scanned)"},
           {&tile_ranges, tiles * 2 * sizeof(std::uint32_t), "tile ranges"},
           {&colour, pixels * 4 * sizeof(float), "colour image"},
           {&depth, pixels * 2 * sizeof(float), "depth image"},
           {&keys[0], pair_capacity * 2 * sizeof(std::uint32_t), "sort keys"},
           {&keys[1], pair_capacity * 2 * sizeof(std::uint32_t), "sort keys"},
           {&values[0], pair_capacity * sizeof(std::uint32_t), "sort values"},
           {&values[1], pair_capacity * sizeof(std::uint32_t), "sort values"},
       })
    if (Status s = vk::EnsureBuffer(c, *buffer, bytes, name); !s.ok()) return s;
  return Status();
}

// Records and runs one frame; *sorted tells which key/value buffer pair holds the sorted result.
Status SplatRenderer::Impl::Record(const FloatCamera& camera, int* sorted) {
  vk::FrameCommands& f = *frame;
  if (Status s = f.Begin(); !s.ok()) return s;
  f.Fill(counters, 0);
  f.Fill(tile_ranges, 0);
  f.Barrier();
  f.Timestamp();
  // 1. Projection, chunk by chunk (push constants: first global index, count).
  for (const vk::GaussianChunk& chunk : gaussians.chunks) {
    const std::uint32_t push[2] = {chunk.first, chunk.count};
    f.Dispatch(*project, {&params, &chunk.geometry, &chunk.sh, &projected, &rects, &tile_counts, &counters},
               push, Groups(chunk.count));
  }
  f.Barrier();
  f.Timestamp();
  // 2. Key offsets = exclusive prefix sum of the tile counts; the total (pairs) goes to counters[0].
  const auto n = static_cast<std::uint32_t>(gaussians.count);
  vk::RecordPrefixSum(f, *prefix_sum, tile_counts, offsets, lane_sums, counters, n, 0);
  f.Timestamp();
  // 3. One (depth, tile) key per touched tile.
  f.Dispatch(*emit, {&params, &rects, &projected, &offsets, &keys[0], &values[0]}, nullptr, Groups(n));
  f.Barrier();
  f.Timestamp();
  // 4. Stable radix sort by (tile, depth).
  const int tile_bits = std::bit_width(static_cast<unsigned>(camera.tiles_x * camera.tiles_y - 1));
  const auto capacity = static_cast<std::uint32_t>(pair_capacity);
  *sorted = vk::RecordRadixSort(f, {histogram.get(), scatter.get(), prefix_sum.get()},
                                {{&keys[0], &keys[1]},
                                 {&values[0], &values[1]},
                                 &histogram_counts,
                                 &histogram_scanned,
                                 &lane_sums,
                                 &counters},
                                tile_bits, sort_lanes, capacity);
  f.Timestamp();
  // 5. Each tile's [begin, end) in the sorted keys.
  const std::uint32_t range_push[2] = {sort_lanes, capacity};
  f.Dispatch(*ranges, {&keys[*sorted], &tile_ranges, &counters}, range_push, Groups(sort_lanes));
  f.Barrier();
  f.Timestamp();
  // 6. Front-to-back blending, one workgroup per tile.
  f.Dispatch(*rasterize, {&params, &tile_ranges, &values[*sorted], &projected, &colour, &depth, &counters},
             nullptr, static_cast<std::uint32_t>(camera.tiles_x), static_cast<std::uint32_t>(camera.tiles_y));
  f.Timestamp();
  return f.SubmitAndWait();
}

Expected<RenderedView> SplatRenderer::Render(const SplatCamera& camera, const RenderSettings& settings) {
  if (Status s = camera.Validate(); !s.ok()) return Status::Error("camera: " + s.message());
  if (Status s = ValidateRenderSettings(settings); !s.ok()) return s;
  Impl& m = *impl_;
  const FloatCamera float_camera = MakeFloatCamera(camera);
  m.stats = SplatFrameStats();
  m.stats.gaussians = m.gaussians.count;
  int sorted = 0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (Status s = m.EnsureFrameBuffers(m.gaussians.count, float_camera); !s.ok()) return s;
    const vk::FrameParams params =
        vk::MakeFrameParams(float_camera, settings, static_cast<std::uint32_t>(m.gaussians.count),
                            m.gaussians.sh_degree, static_cast<std::uint32_t>(m.pair_capacity));
    m.params.Upload(&params, sizeof(params));
    if (Status s = m.Record(float_camera, &sorted); !s.ok()) return s;
    ++m.stats.submissions;
    std::uint32_t counters[kCounters];
    m.counters.Download(counters, sizeof(counters));
    m.stats.tile_gaussian_pairs = counters[0];
    m.stats.visible_gaussians = counters[1];
    m.stats.pixel_gaussian_pairs = (static_cast<std::uint64_t>(counters[3]) << 32) | counters[2];
    if (counters[0] <= m.pair_capacity) break;
    // More tile-Gaussian pairs than key slots: grow (with a margin for the next frames) and render again.
    m.pair_capacity = counters[0] + counters[0] / 4;
  }
  if (m.stats.tile_gaussian_pairs > m.pair_capacity)
    return Status::Error("splat renderer: key buffers did not grow");
  m.last_sorted = sorted;
  m.last_camera = float_camera;
  const std::vector<double> intervals = m.frame->IntervalsMs();
  for (std::size_t i = 0; i < intervals.size() && i < std::size(kStageNames); ++i)
    m.stats.stage_ms.emplace_back(kStageNames[i], intervals[i]);

  RenderedView view = RenderedView::Sized(camera.width, camera.height);
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  const auto* rgba = static_cast<const float*>(m.colour.data());
  const auto* depths = static_cast<const float*>(m.depth.data());
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 3; ++c) view.rgb[3 * p + c] = rgba[4 * p + c];
    view.alpha[p] = rgba[4 * p + 3];
    view.depth[p] = depths[2 * p];
    view.expected_depth[p] = depths[2 * p + 1];
  }
  return view;
}

Expected<GaussianGradients> SplatRenderer::Backward(const ViewGradients& dL_dview) {
  Impl& m = *impl_;
  if (m.last_sorted < 0)
    return Status::Error("splat renderer: Backward needs a Render of the uploaded model");
  const FloatCamera& camera = m.last_camera;
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  auto size_error = [&](const char* field, std::size_t got, std::size_t wanted) {
    return Status::Error("view gradients: " + std::string(field) + " has " + std::to_string(got) +
                         " entries, expected " + std::to_string(wanted) + " (or none)");
  };
  if (dL_dview.rgb.size() != 3 * pixels) return size_error("rgb", dL_dview.rgb.size(), 3 * pixels);
  if (!dL_dview.alpha.empty() && dL_dview.alpha.size() != pixels)
    return size_error("alpha", dL_dview.alpha.size(), pixels);
  if (!dL_dview.depth_sum.empty() && dL_dview.depth_sum.size() != pixels)
    return size_error("depth_sum", dL_dview.depth_sum.size(), pixels);
  if (!m.backward) {
    Expected<std::unique_ptr<vk::BackwardPass>> created = vk::BackwardPass::Create(*m.context);
    if (!created.ok()) return created.status();
    m.backward = std::move(created.value());
  }
  const vk::ForwardState forward{&m.params,      &m.tile_ranges, &m.values[m.last_sorted],
                                 &m.projected,   &m.rects,       &m.offsets,
                                 &m.gaussians,   camera.width,   camera.height,
                                 camera.tiles_x, camera.tiles_y, m.stats.tile_gaussian_pairs};
  if (Status s = m.backward->Prepare(forward); !s.ok()) return s;
  m.backward->UploadViewGradients(dL_dview, pixels);
  if (Status s = m.frame->Begin(); !s.ok()) return s;
  m.backward->Record(*m.frame, forward);
  if (Status s = m.frame->SubmitAndWait(); !s.ok()) return s;
  const std::vector<double> intervals = m.frame->IntervalsMs();
  std::erase_if(m.stats.stage_ms, [](const auto& stage) { return stage.first.ends_with(" backward"); });
  for (std::size_t i = 0; i < intervals.size() && i < 2; ++i)
    m.stats.stage_ms.emplace_back(i == 0 ? "rasterize backward" : "project backward", intervals[i]);
  GaussianGradients gradients;
  m.backward->Download(forward, &gradients);
  return gradients;
}

}  // namespace uf::splat
