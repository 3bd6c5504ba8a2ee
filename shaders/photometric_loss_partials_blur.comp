// Photometric loss, stage 3 of 4 (see photometric_loss.glsl): the row half of the window blur of the SSIM
// partial maps (a, b, c) of stage 2.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
#include "photometric_loss.glsl"

layout(std430, binding = 0) readonly buffer SsimPartials { vec4 ssim_partials[]; };  // 3 vec4 per pixel
layout(std430, binding = 1) writeonly buffer RowPartials { vec4 row_partials[]; };   // 3 vec4 per pixel

void main() {
  int runs = (width + kRun - 1) / kRun, rows = EndRow() - FirstRow();
  for (int item = int(gl_LocalInvocationID.x); item < rows * runs; item += 64) {
    int y = FirstRow() + item / runs, x0 = (item % runs) * kRun;
    uint row = uint(y * width);
    vec4 m[kRun + 2 * kRadius][3];  // the partials of pixels x0 - 5 .. x0 + kRun + 4 (0 outside)
    [[unroll]] for (int i = 0; i < kRun + 2 * kRadius; ++i) {
      int x = x0 - kRadius + i;
      float inside = x >= 0 && x < width ? 1.0 : 0.0;
      uint q = 3 * (row + uint(clamp(x, 0, width - 1)));
      [[unroll]] for (int k = 0; k < 3; ++k) m[i][k] = inside * ssim_partials[q + k];
    }
    [[unroll]] for (int j = 0; j < kRun; ++j) {
      vec4 sum[3] = vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
      [[unroll]] for (int t = 0; t < 2 * kRadius + 1; ++t)
        [[unroll]] for (int k = 0; k < 3; ++k) sum[k] += kWindow[t] * m[j + t][k];
      int x = x0 + j;
      if (x < width) {
        uint p = row + uint(x);
        [[unroll]] for (int k = 0; k < 3; ++k) row_partials[3 * p + k] = sum[k];
      }
    }
  }
}
