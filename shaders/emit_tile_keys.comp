// Tile-key emission: after the exclusive prefix sum of the per-Gaussian tile counts, Gaussian i writes one
// (key, value) pair per touched tile at offsets[i] + j, tiles in row-major order. Emission follows the
// Gaussian index, so the stable radix sort keeps ties of (tile, depth) ordered by index (render rule 4).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "frame_params.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Rects { ivec4 rects[]; };          // from project_gaussians
layout(std430, binding = 2) readonly buffer Projected { vec4 projected[]; };   // 3 vec4 per Gaussian
layout(std430, binding = 3) readonly buffer Offsets { uint offsets[]; };       // exclusive scan of tile counts
// key = (float bits of t_z, tile id = ty * tiles_x + tx): t_z >= near > 0, so the bits sort as the floats.
layout(std430, binding = 4) writeonly buffer Keys { uvec2 keys[]; };
layout(std430, binding = 5) writeonly buffer Values { uint values[]; };        // Gaussian index

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.counts.x) return;
  ivec4 rect = rects[i];
  if (rect.x >= rect.z || rect.y >= rect.w) return;
  uint depth_bits = floatBitsToUint(projected[3 * i + 1].z);
  uint capacity = frame.counts.z;  // pairs beyond the capacity are dropped; the host grows and re-renders
  uint offset = offsets[i];
  for (int ty = rect.y; ty < rect.w; ++ty) {
    for (int tx = rect.x; tx < rect.z; ++tx, ++offset) {
      if (offset >= capacity) return;
      keys[offset] = uvec2(depth_bits, uint(ty * frame.size.z + tx));
      values[offset] = i;
    }
  }
}
