// Radix sort, pass part 1 of 2 (stable LSD sort of uvec2 keys, 8 bits per pass): digit histogram per lane.
// Lane l owns the contiguous key chunk [l * chunk, (l + 1) * chunk), chunk = ceil(count / lanes), and writes
// hist[digit * lanes + l] (digit-major), so an exclusive scan of hist gives every lane's first output slot
// per digit in the stable order (digit, lane, position in chunk). See radix_scatter.comp.
#version 460

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) writeonly buffer Histogram { uint hist[]; };  // 256 * lanes
layout(std430, binding = 2) readonly buffer Counters { uint counters[]; };  // [0]: pairs

layout(push_constant) uniform Push {
  uint word;      // 0: key.x (depth bits), 1: key.y (tile id)
  uint shift;     // bit offset of the digit in the word
  uint lanes;     // invocations in the dispatch
  uint capacity;  // keys allocated; count = min(pairs, capacity)
};

void main() {
  uint lane = gl_GlobalInvocationID.x;
  uint count = min(counters[0], capacity);
  uint chunk = (count + lanes - 1) / lanes;
  uint begin = min(count, lane * chunk), end = min(count, begin + chunk);
  uint h[256];
  for (uint d = 0; d < 256; ++d) h[d] = 0;
  for (uint k = begin; k < end; ++k) h[(keys[k][word] >> shift) & 255u]++;
  for (uint d = 0; d < 256; ++d) hist[d * lanes + lane] = h[d];
}
