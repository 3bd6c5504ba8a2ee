// Backward tile rasterization (render rule 4 of splat/render_types.h backwards; the CPU specification is
// RasterizeReferenceBackward in splat/cpu_reference): dL/d(images) -> dL/d(projected Gaussian), one entry per
// tile-Gaussian pair. One workgroup per 16x16 tile, 64 invocations with 4 pixels each (lavapipe: subgroups of
// 8 lanes on a CPU core; several pixels per invocation amortize the shared-memory loads). Invocation l owns
// the column of 4 pixels x = 8 ((l / 8) % 2) + l % 8, y = 4 (l / 16) + j, so that a subgroup of 8 lanes covers
// a compact 8 x 4 block and skips, in a uniform branch, the Gaussians that cannot reach its block.
//
// Phase 1 replays the forward front to back (same decisions as rasterize_forward.comp) to get per pixel the
// final transmittance T_N and `last` = one past the last blended pair. Phase 2 walks the tile's pairs back to
// front from the largest `last`; per pixel, with T_i the transmittance in front of blended Gaussian i,
// recovered as T_i = T_{i+1} / (1 - a_i) (the same rounded factor the forward multiplied by), and B_i what
// lies behind i (B = bg, then B <- a_i c_i + (1 - a_i) B):
//   dL/dc_i += T_i a_i dL/drgb,   dL/dz_i += T_i a_i dL/dD,
//   dL/da_i  = T_i (dL/drgb . (c_i - B_i) + dL/dA (1 - B^A_i) + dL/dD (z_i - B^D_i))  (B^A: bg 0, colour 1;
//              B^D: bg 0, colour z),
//   a = o G (unclamped), G = exp(power), power = -0.5 (A dx^2 + C dy^2) - B dx dy, (dx, dy) = pixel - (u, v):
//   dL/do += dL/da G,  dL/d(A, B, C) += dL/da o G (-dx^2 / 2, -dx dy, -dy^2 / 2),
//   dL/d(u, v) += dL/da o G (A dx + B dy, B dx + C dy).   (a clamped at max_alpha: only c and z get gradients)
// Per Gaussian of a batch, the invocation sums its pixels, subgroupAdd sums the subgroup, the subgroup
// partials meet in shared memory and one invocation writes the tile's total to the pair's slot. No atomics:
// the result is deterministic.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_EXT_control_flow_attributes : require
#include "frame_params.glsl"

layout(local_size_x = 64) in;
const uint kBatch = 32;
const uint kMaxSubgroups = 16;  // 64 invocations in subgroups of >= 4 lanes
const uint kPixelsPerInvocation = 4;  // a column of 4 pixels per invocation, see above
const uint kFields = 10;

layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Ranges { uvec2 ranges[]; };       // per tile [begin, end)
layout(std430, binding = 2) readonly buffer Values { uint sorted_ids[]; };    // Gaussian index per pair
layout(std430, binding = 3) readonly buffer Projected { vec4 projected[]; };  // see project_gaussians.comp
layout(std430, binding = 4) readonly buffer Rects { ivec4 rects[]; };         // touched tiles [x0, x1) x [y0, y1)
layout(std430, binding = 5) readonly buffer Offsets { uint offsets[]; };      // first pair slot per Gaussian
// dL/d(images), 2 vec4 per pixel: (dL/dr, dL/dg, dL/db, dL/dalpha), (dL/dD, 0, 0, 0), D = sum T a t_z.
layout(std430, binding = 6) readonly buffer ViewGradients { vec4 v_image[]; };
// Output, 10 floats per pair slot: (u, v, conic a, b, c, t_z, r, g, b, opacity). Gaussian i's tile (tx, ty)
// has slot offsets[i] + (ty - y0) (x1 - x0) + (tx - x0), the slot emit_tile_keys.comp gave that pair.
layout(std430, binding = 7) writeonly buffer PairGradients { float v_pairs[]; };

shared vec4 s_mean_conic[kBatch];     // (u, v, conic a, conic b)
shared vec4 s_conic_opacity[kBatch];  // (conic c, opacity, t_z, skip_below: power below it gives alpha < min)
shared vec4 s_colour[kBatch];        // (r, g, b, lambda_min of the conic)
shared uint s_slot[kBatch];
shared float s_partial[kBatch * kFields * kMaxSubgroups];  // [Gaussian][field][subgroup]
shared uint s_finished, s_end;

uint Slot(uint g) {
  ivec4 rect = rects[g];
  return offsets[g] + uint((int(gl_WorkGroupID.y) - rect.y) * (rect.z - rect.x) + int(gl_WorkGroupID.x) - rect.x);
}

void Load(uint pair, uint k, bool with_colour) {
  uint g = sorted_ids[pair];
  vec4 mc = projected[3 * g], co = projected[3 * g + 1];
  s_mean_conic[k] = mc;
  // alpha < min_alpha <=> power < ln(min_alpha / opacity); less a 1e-3 margin, far above rounding.
  s_conic_opacity[k] = vec4(co.xyz, log(frame.blend.x / co.y) - 1e-3);
  // power <= -0.5 lambda_min |d|^2 bounds the Gaussian on any set of pixels by the nearest one (Reaches).
  float mid = 0.5 * (mc.z + co.x), det = mc.z * co.x - mc.w * mc.w;
  float lambda_min = det / (mid + sqrt(max(0.0, mid * mid - det)));
  s_colour[k] = vec4(with_colour ? projected[3 * g + 2].xyz : vec3(0.0), lambda_min);
  if (with_colour) s_slot[k] = Slot(g);
}

// Whether Gaussian k can reach min_alpha at one of the invocation's pixels (x = px, y in [py0, py0 + 3]):
// false only when even the nearest of them has power below skip_below (with a 0.1 % margin).
bool Reaches(uint k, int px, int py0) {
  vec2 mean = s_mean_conic[k].xy;
  vec2 gap = mean - clamp(mean, vec2(px, py0), vec2(px, py0 + 3));
  return -0.5 * 0.999 * s_colour[k].w * dot(gap, gap) >= s_conic_opacity[k].w;
}

// One pixel's part of the back-to-front step for one Gaussian (see the top comment); `g` accumulates the
// invocation's pixels. T_j: transmittance behind the Gaussian on entry, in front of it on return.
struct Gradient {
  vec2 mean;
  vec3 conic, colour;
  float depth, opacity;
  bool touched;
};
void PixelBackward(bool in_front, float dx, float dy, vec4 mc, vec4 co, vec3 colour, vec4 v_rgba, float v_D,
                   inout float T_j, inout float S_j, inout Gradient g) {
  if (!in_front) return;
  float power = -0.5 * (mc.z * dx * dx + co.x * dy * dy) - mc.w * dx * dy;
  if (power < co.w) return;
  float G = exp(power), unclamped = co.y * G;
  float alpha = min(frame.blend.y, unclamped);
  if (alpha < frame.blend.x) return;
  g.touched = true;
  T_j = T_j / (1.0 - alpha);
  float weight = T_j * alpha;
  g.colour += weight * v_rgba.rgb;
  g.depth += weight * v_D;
  float w = dot(v_rgba.rgb, colour) + v_rgba.a + v_D * co.z;
  float v_alpha = T_j * (w - S_j);
  S_j = alpha * w + (1.0 - alpha) * S_j;
  if (unclamped > frame.blend.y) return;  // alpha clamped at max_alpha
  g.opacity += v_alpha * G;
  float v_power = v_alpha * co.y * G;
  g.conic += v_power * vec3(-0.5 * dx * dx, -dx * dy, -0.5 * dy * dy);
  g.mean += v_power * vec2(mc.z * dx + mc.w * dy, mc.w * dx + co.x * dy);
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  int width = frame.size.x, height = frame.size.y;
  uvec2 range = ranges[gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x];
  int px = int(gl_WorkGroupID.x * kTileSize + 8 * ((lid / 8) % 2) + lid % 8);
  int py0 = int(gl_WorkGroupID.y * kTileSize + 4 * (lid / 16));
  float min_alpha = frame.blend.x, max_alpha = frame.blend.y, cutoff = frame.blend.z;

  // Phase 1: the forward, front to back, keeping T_N and one past the last blended pair per pixel.
  float T[kPixelsPerInvocation];
  uint last[kPixelsPerInvocation];
  bool done[kPixelsPerInvocation], inside[kPixelsPerInvocation];
  [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) {
    T[j] = 1.0;
    last[j] = range.x;
    inside[j] = px < width && py0 + int(j) < height;
    done[j] = !inside[j];
  }
  bool finished = done[0] && done[1] && done[2] && done[3];
  if (lid == 0) {
    s_finished = 0;
    s_end = range.x;
  }
  barrier();
  if (finished) atomicAdd(s_finished, 1);
  for (uint batch = range.x; batch < range.y; batch += kBatch) {
    barrier();
    if (s_finished == gl_WorkGroupSize.x) break;
    if (batch + lid < range.y && lid < kBatch) Load(batch + lid, lid, false);
    barrier();
    if (finished) continue;
    uint n = min(kBatch, range.y - batch);
    for (uint k = 0; k < n; ++k) {
      if (!subgroupAny(Reaches(k, px, py0))) continue;  // uniform branch: no pixel of the subgroup
      vec4 mc = s_mean_conic[k], co = s_conic_opacity[k];
      [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) {
        if (done[j]) continue;
        float dx = float(px) - mc.x, dy = float(py0 + int(j)) - mc.y;
        float power = -0.5 * (mc.z * dx * dx + co.x * dy * dy) - mc.w * dx * dy;
        if (power < co.w) continue;
        float alpha = min(max_alpha, co.y * exp(power));
        if (alpha < min_alpha) continue;
        float next_T = T[j] * (1.0 - alpha);
        if (next_T < cutoff) {
          done[j] = true;
          continue;
        }
        T[j] = next_T;
        last[j] = batch + k + 1;
      }
    }
    if (done[0] && done[1] && done[2] && done[3]) {
      finished = true;
      atomicAdd(s_finished, 1);
    }
  }
  uint my_end = max(max(last[0], last[1]), max(last[2], last[3]));
  uint subgroup_end = subgroupMax(my_end);
  if (subgroupElect()) atomicMax(s_end, subgroup_end);
  barrier();
  uint end = s_end;

  // Pairs no pixel reached get zero gradients (every slot of the frame is written exactly once).
  for (uint pair = end + lid; pair < range.y; pair += gl_WorkGroupSize.x) {
    uint slot = Slot(sorted_ids[pair]);
    for (uint f = 0; f < kFields; ++f) v_pairs[kFields * slot + f] = 0.0;
  }

  // Phase 2: back to front.
  // Few registers per pixel (llvmpipe keeps every value as a SIMD register): with the loss-weighted colour
  // w_i = dL/drgb . c_i + dL/dA + dL/dD z_i of Gaussian i, dL/da_i = T_i (w_i - S_i), where
  // S_i = dL/drgb . B_i + dL/dA B^A_i + dL/dD B^D_i obeys the same recursion as B: S = dL/drgb . bg, then
  // S <- a_i w_i + (1 - a_i) S.
  vec4 v_rgba[kPixelsPerInvocation];  // (dL/drgb, dL/dA)
  float v_D[kPixelsPerInvocation], S[kPixelsPerInvocation];
  [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) {
    uint p = uint((py0 + int(j)) * width + px);
    v_rgba[j] = inside[j] ? v_image[2 * p] : vec4(0.0);
    v_D[j] = inside[j] ? v_image[2 * p + 1].x : 0.0;
    S[j] = dot(v_rgba[j].rgb, frame.background.rgb);
  }
  for (uint batch_end = end; batch_end > range.x;) {
    uint n = min(kBatch, batch_end - range.x), batch_start = batch_end - n;
    barrier();  // the previous batch's shared data is consumed
    if (lid < n) Load(batch_start + lid, lid, true);
    barrier();
    for (int k = int(n) - 1; k >= 0; --k) {
      uint pair = batch_start + uint(k);
      vec4 mc = s_mean_conic[k], co = s_conic_opacity[k];
      vec3 colour = s_colour[k].rgb;
      uint base = uint(k) * kFields * kMaxSubgroups + gl_SubgroupID;  // + field * kMaxSubgroups
      // Uniform branch: skip when no pixel of the subgroup is in front of its last pair or reached.
      if (!subgroupAny(pair < my_end && Reaches(k, px, py0))) {
        for (uint f = gl_SubgroupInvocationID; f < kFields; f += gl_SubgroupSize)
          s_partial[base + f * kMaxSubgroups] = 0.0;
        continue;
      }
      Gradient acc = Gradient(vec2(0.0), vec3(0.0), vec3(0.0), 0.0, 0.0, false);
      // The 4 pixels written out (not a loop: llvmpipe then keeps the per-pixel state in registers).
      float dx = float(px) - mc.x, dy = float(py0) - mc.y;
      PixelBackward(pair < last[0], dx, dy, mc, co, colour, v_rgba[0], v_D[0], T[0], S[0], acc);
      PixelBackward(pair < last[1], dx, dy + 1.0, mc, co, colour, v_rgba[1], v_D[1], T[1], S[1], acc);
      PixelBackward(pair < last[2], dx, dy + 2.0, mc, co, colour, v_rgba[2], v_D[2], T[2], S[2], acc);
      PixelBackward(pair < last[3], dx, dy + 3.0, mc, co, colour, v_rgba[3], v_D[3], T[3], S[3], acc);
      // Subgroup sums (skipped when no lane of the subgroup touched the Gaussian: uniform branch).
      if (subgroupAny(acc.touched)) {
        vec2 mean = subgroupAdd(acc.mean);
        vec3 conic = subgroupAdd(acc.conic), colour_sum = subgroupAdd(acc.colour);
        vec2 depth_opacity = subgroupAdd(vec2(acc.depth, acc.opacity));
        // Lane f stores field f (one store per lane instead of ten single-lane stores: cheaper on llvmpipe).
        for (uint f = gl_SubgroupInvocationID; f < kFields; f += gl_SubgroupSize) {
          float v = f < 2   ? mean[f]
                    : f < 5 ? conic[f - 2]
                    : f < 6 ? depth_opacity.x
                    : f < 9 ? colour_sum[f - 6]
                            : depth_opacity.y;
          s_partial[base + f * kMaxSubgroups] = v;
        }
      } else {
        for (uint f = gl_SubgroupInvocationID; f < kFields; f += gl_SubgroupSize)
          s_partial[base + f * kMaxSubgroups] = 0.0;
      }
    }
    barrier();
    if (lid < n) {
      uint slot = s_slot[lid];
      for (uint f = 0; f < kFields; ++f) {
        float total = 0.0;
        for (uint s = 0; s < gl_NumSubgroups; ++s)
          total += s_partial[(lid * kFields + f) * kMaxSubgroups + s];
        v_pairs[kFields * slot + f] = total;
      }
    }
    batch_end = batch_start;
  }
}
