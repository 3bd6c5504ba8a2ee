// Photometric loss, stage 4 of 4 (see photometric_loss.glsl): the column half of the partial-map blur and
// the whole view-gradient image, with per band and subgroup the sums of |r - t| and |E - d| / d (the host adds
// the bands).
// With n = 3 width height, x / y the rendered / target value of a channel and (A, B, C) the blurred (a, b, c):
//   dL/dx = (1 - l) sign(x - y) / n - l / n (A + 2 x B + y C),
// (0 where masked: x is the target there, whatever the render), and where the pixel has a depth pair (count
// of them: m, summed over the slots of stage 1), with
// E = D / alpha and the relative error |E - d| / d: dL/dE = w_d sign(E - d) / (d m), dL/dD = dL/dE / alpha,
// dL/dalpha = -dL/dE E / alpha.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
#include "photometric_loss.glsl"

layout(std430, binding = 0) readonly buffer Colour { vec4 colour[]; };  // rendered (rgb, alpha) per pixel
layout(std430, binding = 1) readonly buffer Depth { vec2 depth[]; };    // rendered (median, expected) depth
layout(std430, binding = 2) readonly buffer Target { vec4 target[]; };  // target (rgb, depth; 0: none)
layout(std430, binding = 3) readonly buffer RowPartials { vec4 row_partials[]; };  // 3 vec4 per pixel
layout(std430, binding = 4) buffer Partials { uint partials[]; };  // see PartialSlot
// Output, 2 vec4 per pixel: (dL/drgb, dL/dalpha), (dL/dD, 0, 0, 0) (splat/vk/backward_pass.h).
layout(std430, binding = 5) writeonly buffer ViewGradients { vec4 v_image[]; };

void main() {
  // The depth pairs of the whole image: stage 1's counts of every band and subgroup (each subgroup adds
  // them up itself: no barrier).
  uint slots = uint((height + kBandRows - 1) / kBandRows) * kMaxSubgroups, pairs = 0;
  for (uint slot = gl_SubgroupInvocationID; slot < slots; slot += gl_SubgroupSize)
    pairs += partials[slot * kPartialWords + 3];
  pairs = subgroupAdd(pairs);
  float dE_scale = pairs > 0 ? depth_weight / float(pairs) : 0.0;
  float inv_n = 1.0 / (3.0 * float(width) * float(height));
  float l1_scale = (1.0 - ssim_weight) * inv_n, ssim_scale = -ssim_weight * inv_n;

  float l1_sum = 0.0, depth_sum = 0.0;
  int y0 = FirstRow(), rows = EndRow() - y0;
  for (int x = int(gl_LocalInvocationID.x); x < width; x += 64) {
    vec4 m[kBandRows + 2 * kRadius][3];  // rows y0 - 5 .. y0 + kBandRows + 4 of column x (0 outside)
    [[unroll]] for (int i = 0; i < kBandRows + 2 * kRadius; ++i) {
      int y = y0 - kRadius + i;
      float inside = y >= 0 && y < height ? 1.0 : 0.0;
      uint q = 3 * (uint(clamp(y, 0, height - 1) * width) + uint(x));
      [[unroll]] for (int k = 0; k < 3; ++k) m[i][k] = inside * row_partials[q + k];
    }
    [[unroll]] for (int j = 0; j < kBandRows; ++j) {
      if (j >= rows) break;  // uniform: the band's last rows may lie below the image
      vec3 A = vec3(0.0), B = vec3(0.0), C = vec3(0.0);
      [[unroll]] for (int t = 0; t < 2 * kRadius + 1; ++t) {
        A += kWindow[t] * m[j + t][0].xyz;
        B += kWindow[t] * m[j + t][1].xyz;
        C += kWindow[t] * m[j + t][2].xyz;
      }
      uint p = uint((y0 + j) * width + x);
      vec4 rendered = colour[p], wanted = target[p];
      float keep = 1.0 - Masked(wanted.w);
      vec3 t = wanted.rgb, r = mix(t, rendered.rgb, keep);
      vec3 g = keep * (l1_scale * sign(r - t) + ssim_scale * (A + 2.0 * r * B + t * C));
      l1_sum += dot(abs(r - t), vec3(1.0));
      float E = depth[p].y, alpha = rendered.a, dD = 0.0, dalpha = 0.0;
      if (HasDepthPair(wanted.w, alpha, E)) {
        depth_sum += abs(E - wanted.w) / wanted.w;
        float dE = dE_scale * sign(E - wanted.w) / wanted.w;
        dD = dE / alpha;
        dalpha = -dE * E / alpha;
      }
      v_image[2 * p] = vec4(g, dalpha);
      v_image[2 * p + 1] = vec4(dD, 0.0, 0.0, 0.0);
    }
  }
  float l1_total = subgroupAdd(l1_sum), depth_total = subgroupAdd(depth_sum);
  if (subgroupElect()) {
    partials[PartialSlot(1)] = floatBitsToUint(l1_total);
    partials[PartialSlot(2)] = floatBitsToUint(depth_total);
  }
}
