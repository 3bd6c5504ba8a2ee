// Tile ranges: in the sorted key array, tile t's pairs occupy [ranges[t].x, ranges[t].y). Each lane scans a
// contiguous chunk and marks where the tile id changes. ranges is zeroed beforehand (empty tiles stay [0, 0)).
#version 460

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Keys { uvec2 keys[]; };  // sorted; .y = tile id
layout(std430, binding = 1) buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = 2) readonly buffer Counters { uint counters[]; };

layout(push_constant) uniform Push {
  uint lanes;
  uint capacity;
};

void main() {
  uint lane = gl_GlobalInvocationID.x;
  uint count = min(counters[0], capacity);
  uint chunk = (count + lanes - 1) / lanes;
  uint begin = min(count, lane * chunk), end = min(count, begin + chunk);
  for (uint k = begin; k < end; ++k) {
    uint tile = keys[k].y;
    if (k == 0 || keys[k - 1].y != tile) ranges[tile].x = k;
    if (k + 1 == count || keys[k + 1].y != tile) ranges[tile].y = k + 1;
  }
}
