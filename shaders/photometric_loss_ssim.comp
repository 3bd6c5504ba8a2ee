// Photometric loss, stage 2 of 4 (see photometric_loss.glsl): the column half of the moment blur, the SSIM
// map S per pixel and channel, its partials and per band the sum of S. With the window moments mu_x, mu_y,
// m_xx, m_yy, m_xy (derivation in splat/cpu_reference/photometric_loss.cpp):
//   s_x = m_xx - mu_x^2, s_y = m_yy - mu_y^2, s_xy = m_xy - mu_x mu_y,
//   A1 = 2 mu_x mu_y + C1, A2 = 2 s_xy + C2, B1 = mu_x^2 + mu_y^2 + C1, B2 = s_x + s_y + C2, S = A1 A2 / (B1 B2),
//   b = dS/dm_xx = -S / B2,  c = dS/dm_xy = 2 A1 / (B1 B2),
//   a = dS/dmu_x = S (2 mu_y / A1 - 2 mu_x / B1) - 2 mu_x b - mu_y c.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
#include "photometric_loss.glsl"

layout(std430, binding = 0) readonly buffer RowMoments { vec4 row_moments[]; };  // 4 vec4 per pixel
layout(std430, binding = 1) writeonly buffer SsimPartials { vec4 ssim_partials[]; };  // (a, b, c) per pixel
layout(std430, binding = 2) buffer Partials { uint partials[]; };  // see PartialSlot

void main() {
  float sum_s = 0.0;
  int y0 = FirstRow(), rows = EndRow() - y0;
  for (int x = int(gl_LocalInvocationID.x); x < width; x += 64) {
    vec4 m[kBandRows + 2 * kRadius][4];  // rows y0 - 5 .. y0 + kBandRows + 4 of column x (0 outside)
    [[unroll]] for (int i = 0; i < kBandRows + 2 * kRadius; ++i) {
      int y = y0 - kRadius + i;
      float inside = y >= 0 && y < height ? 1.0 : 0.0;
      uint q = 4 * (uint(clamp(y, 0, height - 1) * width) + uint(x));
      [[unroll]] for (int k = 0; k < 4; ++k) m[i][k] = inside * row_moments[q + k];
    }
    [[unroll]] for (int j = 0; j < kBandRows; ++j) {
      if (j >= rows) break;  // uniform: the band's last rows may lie below the image
      vec4 sum[4] = vec4[4](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
      [[unroll]] for (int t = 0; t < 2 * kRadius + 1; ++t)
        [[unroll]] for (int k = 0; k < 4; ++k) sum[k] += kWindow[t] * m[j + t][k];
      vec3 mx, my, mxx, myy, mxy;
      UnpackMoments(sum, mx, my, mxx, myy, mxy);
      vec3 s_x = mxx - mx * mx, s_y = myy - my * my, s_xy = mxy - mx * my;
      vec3 A1 = 2.0 * mx * my + kC1, A2 = 2.0 * s_xy + kC2;
      vec3 B1 = mx * mx + my * my + kC1, B2 = s_x + s_y + kC2;
      vec3 S = A1 * A2 / (B1 * B2);
      vec3 b = -S / B2, c = 2.0 * A1 / (B1 * B2);
      vec3 a = S * (2.0 * my / A1 - 2.0 * mx / B1) - 2.0 * mx * b - my * c;
      uint p = uint((y0 + j) * width + x);
      ssim_partials[3 * p] = vec4(a, 0.0);
      ssim_partials[3 * p + 1] = vec4(b, 0.0);
      ssim_partials[3 * p + 2] = vec4(c, 0.0);
      sum_s += S.r + S.g + S.b;
    }
  }
  float total = subgroupAdd(sum_s);
  if (subgroupElect()) partials[PartialSlot(0)] = floatBitsToUint(total);
}
