#include "splat/vk/forward_pass.h"

#include <algorithm>
#include <bit>
#include <tuple>

#include "shaders/embedded_shaders.h"
#include "splat/vk/frame_params.h"
#include "splat/vk/gpu_primitives.h"

namespace uf::splat::vk {

namespace {

constexpr std::uint32_t kWorkgroup = 64;
constexpr std::uint32_t kCounters = 8;  // see shaders/frame_params.glsl (0..3) and gpu_primitives.cpp (4)
constexpr std::size_t kProjectedBytes = 3 * 4 * sizeof(float);

std::uint32_t Groups(std::size_t n) { return static_cast<std::uint32_t>((n + kWorkgroup - 1) / kWorkgroup); }

}  // namespace

Expected<std::unique_ptr<ForwardPass>> ForwardPass::Create(const Context& context) {
  std::unique_ptr<ForwardPass> pass(new ForwardPass(context));
  // Radix-sort lanes (each sorts a contiguous chunk serially): a few per CPU core on lavapipe, many on a GPU.
  pass->sort_lanes_ = context.is_cpu() ? 256 : 8192;
  const struct {
    std::unique_ptr<ComputePipeline>* pipeline;
    ShaderId id;
    std::uint32_t bindings, push_bytes;
    const char* name;
  } pipelines[] = {
      {&pass->project_, ShaderId::kProjectGaussians, 7, 8, "project_gaussians"},
      {&pass->emit_, ShaderId::kEmitTileKeys, 6, 0, "emit_tile_keys"},
      {&pass->prefix_sum_, ShaderId::kPrefixSum, 4, 12, "prefix_sum"},
      {&pass->histogram_, ShaderId::kRadixHistogram, 3, 16, "radix_histogram"},
      {&pass->scatter_, ShaderId::kRadixScatter, 6, 16, "radix_scatter"},
      {&pass->ranges_, ShaderId::kTileRanges, 3, 8, "tile_ranges"},
      {&pass->rasterize_, ShaderId::kRasterizeForward, 8, 0, "rasterize_forward"},
  };
  for (const auto& p : pipelines) {
    auto created = ComputePipeline::Create(context, ShaderCode(p.id), p.bindings, p.push_bytes, p.name);
    if (!created.ok()) return created.status();
    *p.pipeline = std::move(created.value());
  }
  return pass;
}

Status ForwardPass::Prepare(const GaussianBuffers& gaussians, const FloatCamera& camera,
                            const RenderSettings& settings, int active_sh_degree) {
  const std::size_t n = gaussians.count;
  // The projected records of all Gaussians sit in one buffer, bound whole.
  const std::size_t limit = context_.limits().maxStorageBufferRange;
  if (n * kProjectedBytes > limit)
    return Status::Error("splats: " + std::to_string(n) + " Gaussians exceed the renderer's limit of " +
                         std::to_string(limit / kProjectedBytes) + " on " + context_.device_name());
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  const std::size_t tiles = static_cast<std::size_t>(camera.tiles_x) * camera.tiles_y;
  // A first guess of the tile-Gaussian pairs (grown by Finish when a frame has more): one per Gaussian, so
  // that the backward's per-pair records (48 bytes each) of a large model do not start over the binding
  // limit.
  if (pair_capacity_ == 0) pair_capacity_ = std::max<std::size_t>(4096, n);
  const std::size_t histogram_bytes = 256 * sizeof(std::uint32_t) * sort_lanes_;
  for (const auto& [buffer, bytes, name] : {
           std::tuple{&params_, sizeof(FrameParams), "frame parameters"},
           {&counters_, kCounters * sizeof(std::uint32_t), "counters"},
           {&projected_, n * kProjectedBytes, "projected Gaussians"},
           {&rects_, n * 4 * sizeof(std::int32_t), "tile rectangles"},
           {&tile_counts_, n * sizeof(std::uint32_t), "tile counts"},
           {&offsets_, n * sizeof(std::uint32_t), "key offsets"},
           {&lane_sums_, kScanLanes * sizeof(std::uint32_t), "prefix-sum scratch"},
           {&histogram_counts_, histogram_bytes, "radix histogram"},
           {&histogram_scanned_, histogram_bytes, "radix histogram (scanned)"},
           {&tile_ranges_, tiles * 2 * sizeof(std::uint32_t), "tile ranges"},
           {&colour_, pixels * 4 * sizeof(float), "colour image"},
           {&depth_, pixels * 2 * sizeof(float), "depth image"},
           {&pixel_state_, pixels * 2 * sizeof(std::uint32_t), "pixel blending state"},
           {&keys_[0], pair_capacity_ * 2 * sizeof(std::uint32_t), "sort keys"},
           {&keys_[1], pair_capacity_ * 2 * sizeof(std::uint32_t), "sort keys"},
           {&values_[0], pair_capacity_ * sizeof(std::uint32_t), "sort values"},
           {&values_[1], pair_capacity_ * sizeof(std::uint32_t), "sort values"},
       })
    if (Status s = EnsureBuffer(context_, *buffer, std::max<std::size_t>(bytes, 4), name); !s.ok()) return s;
  camera_ = camera;
  const FrameParams params =
      MakeFrameParams(camera, settings, static_cast<std::uint32_t>(n), gaussians.sh_degree,
                      static_cast<std::uint32_t>(pair_capacity_), active_sh_degree);
  params_.Upload(&params, sizeof(params));
  return Status();
}

void ForwardPass::Record(FrameCommands& f, const GaussianBuffers& gaussians) {
  f.Fill(counters_, 0);
  f.Fill(tile_ranges_, 0);
  f.Barrier();
  f.Timestamp();
  // 1. Projection, chunk by chunk (push constants: first global index, count).
  for (const GaussianChunk& chunk : gaussians.chunks) {
    const std::uint32_t push[2] = {chunk.first, chunk.count};
    f.Dispatch(*project_,
               {&params_, &chunk.geometry, &chunk.sh, &projected_, &rects_, &tile_counts_, &counters_}, push,
               Groups(chunk.count));
  }
  f.Barrier();
  f.Timestamp();
  // 2. Key offsets = exclusive prefix sum of the tile counts; the total (pairs) goes to counters[0].
  const auto n = static_cast<std::uint32_t>(gaussians.count);
  RecordPrefixSum(f, *prefix_sum_, tile_counts_, offsets_, lane_sums_, counters_, n, 0);
  f.Timestamp();
  // 3. One (depth, tile) key per touched tile.
  f.Dispatch(*emit_, {&params_, &rects_, &projected_, &offsets_, &keys_[0], &values_[0]}, nullptr, Groups(n));
  f.Barrier();
  f.Timestamp();
  // 4. Stable radix sort by (tile, depth).
  const int tile_bits = std::bit_width(static_cast<unsigned>(camera_.tiles_x * camera_.tiles_y - 1));
  const auto capacity = static_cast<std::uint32_t>(pair_capacity_);
  sorted_ = RecordRadixSort(f, {histogram_.get(), scatter_.get(), prefix_sum_.get()},
                            {{&keys_[0], &keys_[1]},
                             {&values_[0], &values_[1]},
                             &histogram_counts_,
                             &histogram_scanned_,
                             &lane_sums_,
                             &counters_},
                            tile_bits, sort_lanes_, capacity);
  f.Timestamp();
  // 5. Each tile's [begin, end) in the sorted keys.
  const std::uint32_t range_push[2] = {sort_lanes_, capacity};
  f.Dispatch(*ranges_, {&keys_[sorted_], &tile_ranges_, &counters_}, range_push, Groups(sort_lanes_));
  f.Barrier();
  f.Timestamp();
  // 6. Front-to-back blending, one workgroup per tile.
  f.Dispatch(
      *rasterize_,
      {&params_, &tile_ranges_, &values_[sorted_], &projected_, &colour_, &depth_, &counters_, &pixel_state_},
      nullptr, static_cast<std::uint32_t>(camera_.tiles_x), static_cast<std::uint32_t>(camera_.tiles_y));
  f.Barrier();
  f.Timestamp();
}

bool ForwardPass::Finish(SplatFrameStats* stats) {
  std::uint32_t counters[kCounters];
  counters_.Download(counters, sizeof(counters));
  stats->tile_gaussian_pairs = counters[0];
  stats->visible_gaussians = counters[1];
  stats->pixel_gaussian_pairs = (static_cast<std::uint64_t>(counters[3]) << 32) | counters[2];
  if (counters[0] <= pair_capacity_) return true;
  // More tile-Gaussian pairs than key slots: grow (with a margin for the next frames).
  pair_capacity_ = counters[0] + counters[0] / 4;
  sorted_ = -1;
  return false;
}

void ForwardPass::ReadView(RenderedView* view) const {
  *view = RenderedView::Sized(camera_.width, camera_.height);
  const std::size_t pixels = static_cast<std::size_t>(camera_.width) * camera_.height;
  const auto* rgba = static_cast<const float*>(colour_.data());
  const auto* depths = static_cast<const float*>(depth_.data());
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 3; ++c) view->rgb[3 * p + c] = rgba[4 * p + c];
    view->alpha[p] = rgba[4 * p + 3];
    view->depth[p] = depths[2 * p];
    view->expected_depth[p] = depths[2 * p + 1];
  }
}

ForwardState ForwardPass::State(const GaussianBuffers& gaussians) const {
  ForwardState state;
  state.params = &params_;
  state.tile_ranges = &tile_ranges_;
  state.sorted_ids = sorted_ >= 0 ? &values_[sorted_] : nullptr;
  state.projected = &projected_;
  state.rects = &rects_;
  state.offsets = &offsets_;
  state.pixel_state = &pixel_state_;
  state.gaussians = &gaussians;
  state.width = camera_.width;
  state.height = camera_.height;
  state.tiles_x = camera_.tiles_x;
  state.tiles_y = camera_.tiles_y;
  state.pairs = pair_capacity_;
  return state;
}

}  // namespace uf::splat::vk
