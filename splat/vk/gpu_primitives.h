// Recording of the generic GPU primitives of the splat pipeline into a frame's command buffer: the exclusive
// prefix sum (shaders/prefix_sum.comp) and the stable LSD radix sort of (depth bits, tile id) keys with
// their values (shaders/radix_histogram.comp + radix_scatter.comp).
#pragma once

#include <cstdint>

#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/frame_commands.h"

namespace uf::splat::vk {

inline constexpr std::uint32_t kScanLanes = 1024;  // must equal kLanes in shaders/prefix_sum.comp

// output[k] = sum of input[0 .. k) for k < n; counters[total_index] = the total. lane_sums: kScanLanes
// uints of scratch. Ends with a barrier.
void RecordPrefixSum(FrameCommands& frame, const ComputePipeline& prefix_sum, const Buffer& input,
                     const Buffer& output, const Buffer& lane_sums, const Buffer& counters, std::uint32_t n,
                     std::uint32_t total_index);

struct RadixSortBuffers {
  const Buffer* keys[2];    // uvec2 (depth bits, tile id); the input is keys[0]
  const Buffer* values[2];  // uint
  const Buffer* histogram;  // 256 * lanes uints
  const Buffer* histogram_scanned;
  const Buffer* lane_sums;  // prefix-sum scratch
  const Buffer* counters;   // counters[0] = number of keys (clamped to capacity in the shaders)
};

struct RadixSortPipelines {
  const ComputePipeline* histogram;
  const ComputePipeline* scatter;
  const ComputePipeline* prefix_sum;
};

// Sorts by (tile id, depth bits), stable: 4 passes of 8 bits over the depth word, then ceil(tile_bits / 8)
// over the tile word (least significant digit first). `lanes` invocations each own a contiguous chunk of
// keys. Returns which of the two buffer pairs holds the result. counters[1] is not touched; the histogram
// totals go to counters[4].
int RecordRadixSort(FrameCommands& frame, const RadixSortPipelines& pipelines,
                    const RadixSortBuffers& buffers, int tile_bits, std::uint32_t lanes,
                    std::uint32_t capacity);

}  // namespace uf::splat::vk
