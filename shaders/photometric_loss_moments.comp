// Photometric loss, stage 1 of 4 (see photometric_loss.glsl): the row half of the SSIM window blur of the
// five moment images x, y, x^2, y^2, xy (x rendered rgb, the target's where masked; y target rgb; packed in 4
// vec4 per pixel), and per
// band and subgroup the number of pixels with a depth pair (stage 4 normalizes the depth term by the total).
// The depth-pair test takes alpha and target depth from the run's own colour / target loads instead of
// loading them again (on lavapipe each per-lane load is a loop over the lanes: 2 of 3 loads per pixel saved).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
#include "photometric_loss.glsl"

layout(std430, binding = 0) readonly buffer Colour { vec4 colour[]; };  // rendered (rgb, alpha) per pixel
layout(std430, binding = 1) readonly buffer Depth { vec2 depth[]; };    // rendered (median, expected) depth
layout(std430, binding = 2) readonly buffer Target { vec4 target[]; };  // target (rgb, depth; 0: none)
// Output, 4 vec4 per pixel: the row blur of the packed moments (PackMoments).
layout(std430, binding = 3) writeonly buffer RowMoments { vec4 row_moments[]; };
layout(std430, binding = 4) buffer Partials { uint partials[]; };  // see PartialSlot

void main() {
  int runs = (width + kRun - 1) / kRun, rows = EndRow() - FirstRow();
  uint valid = 0;
  for (int item = int(gl_LocalInvocationID.x); item < rows * runs; item += 64) {
    int y = FirstRow() + item / runs, x0 = (item % runs) * kRun;
    uint row = uint(y * width);
    vec4 m[kRun + 2 * kRadius][4];  // the packed moments of pixels x0 - 5 .. x0 + kRun + 4 (0 outside)
    float alpha[kRun], target_depth[kRun];  // of the run's own pixels, kept from the loads above
    [[unroll]] for (int i = 0; i < kRun + 2 * kRadius; ++i) {
      int x = x0 - kRadius + i;
      float inside = x >= 0 && x < width ? 1.0 : 0.0;
      uint q = row + uint(clamp(x, 0, width - 1));
      vec4 c = colour[q], t = target[q];
      PackMoments(inside * mix(c.rgb, t.rgb, Masked(t.w)), inside * t.rgb, m[i]);
      if (i >= kRadius && i < kRadius + kRun) {  // compile-time condition (unrolled)
        alpha[i - kRadius] = c.a;
        target_depth[i - kRadius] = t.w;
      }
    }
    [[unroll]] for (int j = 0; j < kRun; ++j) {
      vec4 sum[4] = vec4[4](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
      [[unroll]] for (int t = 0; t < 2 * kRadius + 1; ++t)
        [[unroll]] for (int k = 0; k < 4; ++k) sum[k] += kWindow[t] * m[j + t][k];
      int x = x0 + j;
      if (x < width) {
        uint p = row + uint(x);
        [[unroll]] for (int k = 0; k < 4; ++k) row_moments[4 * p + k] = sum[k];
        if (HasDepthPair(target_depth[j], alpha[j], depth[p].y)) ++valid;
      }
    }
  }
  uint total = subgroupAdd(valid);
  if (subgroupElect()) partials[PartialSlot(3)] = total;
}
