#include "splat/vk/gpu_primitives.h"

namespace uf::splat::vk {

namespace {

constexpr std::uint32_t kWorkgroup = 64;
constexpr std::uint32_t kCounterSortTotal = 4;  // scratch counter for the histogram scans

struct ScanPush {
  std::uint32_t n, phase, total_index;
};

struct SortPush {
  std::uint32_t word, shift, lanes, capacity;
};

}  // namespace

void RecordPrefixSum(FrameCommands& frame, const ComputePipeline& prefix_sum, const Buffer& input,
                     const Buffer& output, const Buffer& lane_sums, const Buffer& counters, std::uint32_t n,
                     std::uint32_t total_index) {
  for (std::uint32_t phase = 0; phase < 3; ++phase) {
    const ScanPush push{n, phase, total_index};
    frame.Dispatch(prefix_sum, {&input, &output, &lane_sums, &counters}, &push,
                   phase == 1 ? 1 : kScanLanes / kWorkgroup);
    frame.Barrier();
  }
}

int RecordRadixSort(FrameCommands& frame, const RadixSortPipelines& pipelines,
                    const RadixSortBuffers& buffers, int tile_bits, std::uint32_t lanes,
                    std::uint32_t capacity) {
  int current = 0;
  const int tile_passes = (tile_bits + 7) / 8;
  for (int pass = 0; pass < 4 + tile_passes; ++pass) {
    // Least significant digit first: depth bytes 0..3, then tile bytes.
    const SortPush push{pass < 4 ? 0u : 1u, 8u * static_cast<std::uint32_t>(pass < 4 ? pass : pass - 4),
                        lanes, capacity};
    const std::uint32_t groups = (lanes + kWorkgroup - 1) / kWorkgroup;
    frame.Dispatch(*pipelines.histogram, {buffers.keys[current], buffers.histogram, buffers.counters}, &push,
                   groups);
    frame.Barrier();
    RecordPrefixSum(frame, *pipelines.prefix_sum, *buffers.histogram, *buffers.histogram_scanned,
                    *buffers.lane_sums, *buffers.counters, 256 * lanes, kCounterSortTotal);
    frame.Dispatch(*pipelines.scatter,
                   {buffers.keys[current], buffers.values[current], buffers.keys[1 - current],
                    buffers.values[1 - current], buffers.histogram_scanned, buffers.counters},
                   &push, groups);
    frame.Barrier();
    current = 1 - current;
  }
  return current;
}

}  // namespace uf::splat::vk
