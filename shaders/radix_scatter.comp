// Radix sort, pass part 2 of 2: stable scatter. After the exclusive scan of the digit-major histogram
// (radix_histogram.comp, prefix_sum.comp), lane l walks its chunk in order and moves each (key, value) to
// the next slot of its digit, so equal digits keep their input order: the pass is stable, and the LSD
// passes over depth bits then tile bits sort by (tile, depth, emission order = Gaussian index).
#version 460

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer KeysIn { uvec2 keys_in[]; };
layout(std430, binding = 1) readonly buffer ValuesIn { uint values_in[]; };
layout(std430, binding = 2) writeonly buffer KeysOut { uvec2 keys_out[]; };
layout(std430, binding = 3) writeonly buffer ValuesOut { uint values_out[]; };
layout(std430, binding = 4) readonly buffer Histogram { uint first_slot[]; };  // scanned, digit-major
layout(std430, binding = 5) readonly buffer Counters { uint counters[]; };     // [0]: pairs

layout(push_constant) uniform Push {
  uint word;
  uint shift;
  uint lanes;
  uint capacity;
};

void main() {
  uint lane = gl_GlobalInvocationID.x;
  uint count = min(counters[0], capacity);
  uint chunk = (count + lanes - 1) / lanes;
  uint begin = min(count, lane * chunk), end = min(count, begin + chunk);
  if (begin == end) return;
  uint slot[256];
  for (uint d = 0; d < 256; ++d) slot[d] = first_slot[d * lanes + lane];
  for (uint k = begin; k < end; ++k) {
    uvec2 key = keys_in[k];
    uint destination = slot[(key[word] >> shift) & 255u]++;
    keys_out[destination] = key;
    values_out[destination] = values_in[k];
  }
}
