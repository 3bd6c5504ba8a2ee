// Backward tile rasterization (render rule 4 of splat/render_types.h backwards; the CPU specification is
// RasterizeReferenceBackward in splat/cpu_reference): dL/d(images) -> dL/d(projected Gaussian), one record per
// tile-Gaussian pair. Same layout as rasterize_forward.comp: one workgroup per 16x16 tile, split into four
// 8x8 blocks of 8 invocations (lavapipe's subgroup); lane l of a block owns the pixel column x = l, rows 0..7.
//
// Per pixel the forward left (pixel_state) its final transmittance T_N and `end`: the pixel blended exactly
// the pairs before `end` whose alpha reaches min_alpha. Walking the tile's pairs back to front, with T_i the
// transmittance in front of blended Gaussian i, recovered as T_i = T_{i+1} / (1 - a_i) (the same rounded
// factor the forward multiplied by), and B_i what lies behind i (B = bg, then B <- a_i c_i + (1 - a_i) B):
//   dL/dc_i += T_i a_i dL/drgb,   dL/dz_i += T_i a_i dL/dD,
//   dL/da_i  = T_i (dL/drgb . (c_i - B_i) + dL/dA (1 - B^A_i) + dL/dD (z_i - B^D_i))  (B^A: bg 0, colour 1;
//              B^D: bg 0, colour z),
//   a = o G (unclamped), G = exp(power), power = -0.5 (A dx^2 + C dy^2) - B dx dy, (dx, dy) = pixel - (u, v):
//   dL/do += dL/da G,  dL/d(A, B, C) += dL/da o G (-dx^2 / 2, -dx dy, -dy^2 / 2),
//   dL/d(u, v) += dL/da o G (A dx + B dy, B dx + C dy).   (a clamped at max_alpha: only c and z get gradients)
// Few registers per pixel: with w_i = dL/drgb . c_i + dL/dA + dL/dD z_i, dL/da_i = T_i (w_i - S_i), where
// S_i = dL/drgb . B_i + dL/dA B^A_i + dL/dD B^D_i obeys the recursion of B: S = dL/drgb . bg, then
// S <- a_i w_i + (1 - a_i) S.
//
// Why it is fast on lavapipe (an `if` runs both sides under a mask; reductions such as subgroupAdd and every
// shared/storage access with per-lane addresses are loops over the 8 lanes, xor shuffles are not; only loop
// trip counts save work): as in the forward, each batch of 64 pairs gets one 64-bit mask per block of the
// Gaussians that may reach min_alpha on it (a superset of what the forward blended there), cut at the block's
// largest `end`; each block loops over its set bits only, highest first (= back to front). Per (block,
// Gaussian): 3 shared loads, 10 block sums (xor butterflies, see BlockSum), one shared store of the block's
// record; each pair's record is then the sum of its blocks' records in block order. No atomics on floats: the
// result is deterministic. The invocation that loads a pair keeps its slot and which blocks it may reach in
// registers for that sum, and every invocation keeps the blocks' `end` in registers: fewer shared accesses
// (each one a loop over the lanes) per pair.
// Tried and slower on lavapipe: a transposing butterfly (10 shuffles, each lane storing 2 of the 10 sums:
// per-lane stores cost more than the shuffles saved), loading the Gaussian on the block's first lane and
// broadcasting it, exp2 with a pre-scaled conic, batches of 32 pairs, 8x4 blocks.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_EXT_control_flow_attributes : require
#include "frame_params.glsl"

const uint kRows = 8;                                 // pixels per invocation: a column of its block
const uint kBlockWidth = 8;                           // columns of a block (one per lane)
const uint kBlocksX = kTileSize / kBlockWidth;        // 2
const uint kBlocks = kBlocksX * (kTileSize / kRows);  // 4
const uint kInvocations = kBlocks * kBlockWidth;      // 32
const uint kBatch = 64;                               // pairs per batch: two mask words
const uint kLoadsPerInvocation = kBatch / kInvocations;
layout(local_size_x = kInvocations) in;

// The frame parameters this shader needs (as FrameParams; pushed: the pass has one binding left for them).
layout(push_constant) uniform Push {
  ivec4 size;        // width, height, tiles_x, tiles_y
  vec4 blend;        // min_alpha, max_alpha, transmittance_cutoff, 0
  vec4 background;   // rgb, 0
  uvec4 pages;       // slots per page of pair records, 0, 0, 0
};
layout(std430, binding = 0) readonly buffer Ranges { uvec2 ranges[]; };       // per tile [begin, end)
layout(std430, binding = 1) readonly buffer Values { uint sorted_ids[]; };    // Gaussian index per pair
layout(std430, binding = 2) readonly buffer Projected { vec4 projected[]; };  // see project_gaussians.comp
layout(std430, binding = 3) readonly buffer Rects { ivec4 rects[]; };         // touched tiles [x0, x1) x [y0, y1)
layout(std430, binding = 4) readonly buffer Offsets { uint offsets[]; };      // first pair slot per Gaussian
// dL/d(images), 2 vec4 per pixel: (dL/dr, dL/dg, dL/db, dL/dalpha), (dL/dD, 0, 0, 0), D = sum T a t_z.
layout(std430, binding = 5) readonly buffer ViewGradients { vec4 v_image[]; };
layout(std430, binding = 6) readonly buffer PixelState { uvec2 pixel_state[]; };  // (T_N bits, end) per pixel
// Output, 3 vec4 per pair slot: (u, v, conic a, conic b), (conic c, t_z, r, g), (b, opacity, 0, 0). Gaussian
// i's tile (tx, ty) has slot offsets[i] + (ty - y0) (x1 - x0) + (tx - x0), the slot emit_tile_keys.comp gave.
// Three pages of S = pages.x slots, each under the device's binding limit (splat/vk/backward_pass.h): slot s
// is record s - p S of page p = s / S.
layout(std430, binding = 7) writeonly buffer PairPage0 { vec4 v_page0[]; };
layout(std430, binding = 8) writeonly buffer PairPage1 { vec4 v_page1[]; };
layout(std430, binding = 9) writeonly buffer PairPage2 { vec4 v_page2[]; };

shared vec4 s_mean_conic[kBatch];             // (u, v, conic a, conic b)
shared vec4 s_conic_opacity[kBatch];          // (conic c, opacity, t_z, colour r)
shared vec2 s_colour_gb[kBatch];              // (colour g, colour b)
shared uint s_block_mask[2][kBlocks][2];      // [batch parity][block][word]: Gaussians that may reach it
shared uint s_block_end[kBlocks];             // largest pixel `end` of the block
shared uint s_tile_end;
shared vec4 s_record[kBatch][kBlocks][3];     // per pair and block: the block's sums, laid out as v_pairs

// Sum over the 8 lanes of a block: a butterfly of shuffles, also where the subgroup is the block (lavapipe's
// subgroupAdd is a loop over the lanes, its xor shuffles are cheap: this took ~25 % off the shader's time).
float BlockSum(float x) {
  x += subgroupShuffleXor(x, 1);
  x += subgroupShuffleXor(x, 2);
  return x + subgroupShuffleXor(x, 4);
}
vec2 BlockSum(vec2 x) { return vec2(BlockSum(x.x), BlockSum(x.y)); }
vec3 BlockSum(vec3 x) { return vec3(BlockSum(x.x), BlockSum(x.y), BlockSum(x.z)); }
// Max over the 8 lanes of a block: the whole subgroup on lavapipe, else a butterfly within groups of 8.
uint BlockMax(uint x) {
  if (gl_SubgroupSize == kBlockWidth) return subgroupMax(x);
  x = max(x, subgroupShuffleXor(x, 1));
  x = max(x, subgroupShuffleXor(x, 2));
  return max(x, subgroupShuffleXor(x, 4));
}

// min over d in [lo, hi] (a box) of q(d) = a dx^2 + 2 b dx dy + c dy^2 (a, c > 0, ac > b^2), as in
// rasterize_forward.comp: 0 when the box holds the origin, else the minimum lies on an edge.
float MinQuadraticOverRect(vec2 lo, vec2 hi, float a, float b, float c) {
  if (all(lessThanEqual(lo, vec2(0.0))) && all(greaterThanEqual(hi, vec2(0.0)))) return 0.0;
  float best = uintBitsToFloat(0x7f800000u);
  [[unroll]] for (uint e = 0; e < 2; ++e) {
    float x = e == 0 ? lo.x : hi.x, y = clamp(-b * x / c, lo.y, hi.y);
    best = min(best, a * x * x + 2.0 * b * x * y + c * y * y);
    y = e == 0 ? lo.y : hi.y;
    x = clamp(-b * y / a, lo.x, hi.x);
    best = min(best, a * x * x + 2.0 * b * x * y + c * y * y);
  }
  return best;
}

uint Slot(uint g) {
  ivec4 rect = rects[g];
  return offsets[g] + uint((int(gl_WorkGroupID.y) - rect.y) * (rect.z - rect.x) + int(gl_WorkGroupID.x) - rect.x);
}

void StoreRecord(uint slot, vec4 record[3]) {
  uint page = slot / pages.x, i = 3 * (slot - page * pages.x);
  if (page == 0) {
    [[unroll]] for (uint r = 0; r < 3; ++r) v_page0[i + r] = record[r];
  } else if (page == 1) {
    [[unroll]] for (uint r = 0; r < 3; ++r) v_page1[i + r] = record[r];
  } else {
    [[unroll]] for (uint r = 0; r < 3; ++r) v_page2[i + r] = record[r];
  }
}

// Bits [0, n) of a mask word (n clamped to [0, 32]).
uint LowBits(int n) { return n >= 32 ? 0xffffffffu : n <= 0 ? 0u : (1u << uint(n)) - 1u; }

void main() {
  uint lid = gl_LocalInvocationID.x;
  uint block = lid / kBlockWidth;
  int width = size.x, height = size.y;
  uvec2 range = ranges[gl_WorkGroupID.y * size.z + gl_WorkGroupID.x];
  ivec2 tile_first_pixel = ivec2(gl_WorkGroupID.xy * kTileSize);
  ivec2 block_first_pixel =
      tile_first_pixel + ivec2((block % kBlocksX) * kBlockWidth, (block / kBlocksX) * kRows);
  int px = block_first_pixel.x + int(lid % kBlockWidth), py0 = block_first_pixel.y;
  float min_alpha = blend.x, max_alpha = blend.y;

  // Per pixel: T (behind the current Gaussian, in front of it after its step), S, dL/d(rgb, A), dL/dD, end.
  float T[kRows], S[kRows], v_D[kRows];
  vec4 v_rgba[kRows];
  uint end[kRows];
  uint my_end = range.x;
  [[unroll]] for (uint j = 0; j < kRows; ++j) {
    bool inside = px < width && py0 + int(j) < height;
    uint p = inside ? uint((py0 + int(j)) * width + px) : 0u;
    uvec2 state = pixel_state[p];
    T[j] = uintBitsToFloat(state.x);
    end[j] = inside ? state.y : range.x;
    v_rgba[j] = inside ? v_image[2 * p] : vec4(0.0);
    v_D[j] = inside ? v_image[2 * p + 1].x : 0.0;
    S[j] = dot(v_rgba[j].rgb, background.rgb);
    my_end = max(my_end, end[j]);
  }
  uint block_end = BlockMax(my_end);
  if (lid == 0) s_tile_end = range.x;
  if (lid < kBlocks * 2) {
    s_block_mask[0][lid / 2][lid % 2] = 0;
    s_block_mask[1][lid / 2][lid % 2] = 0;
  }
  barrier();
  if (lid % kBlockWidth == 0) {
    s_block_end[block] = block_end;
    atomicMax(s_tile_end, block_end);
  }
  barrier();
  uint tile_end = s_tile_end;
  // Kept in registers (a shared load with per-lane addresses is a loop over the lanes on lavapipe).
  uint block_ends[kBlocks];
  [[unroll]] for (uint b = 0; b < kBlocks; ++b) block_ends[b] = s_block_end[b];

  // Pairs no pixel reached get zero records (every slot of the frame is written exactly once).
  for (uint pair = tile_end + lid; pair < range.y; pair += kInvocations) {
    StoreRecord(Slot(sorted_ids[pair]), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)));
  }

  uint parity = 0;
  // Per pair this invocation loads: its slot and the blocks it may reach (used again to combine the records).
  uint slots[kLoadsPerInvocation];
  bool reaches[kLoadsPerInvocation][kBlocks];
  for (uint batch_end = tile_end; batch_end > range.x; parity ^= 1) {
    uint n = min(kBatch, batch_end - range.x), batch_start = batch_end - n;
    barrier();  // the previous batch's records and masks are consumed
    // Load: each invocation brings kLoadsPerInvocation pairs and marks the blocks their Gaussian may reach.
    [[unroll]] for (uint i = 0; i < kLoadsPerInvocation; ++i) {
      uint q = i * kInvocations + lid;
      if (q < n) {
        uint g = sorted_ids[batch_start + q];
        vec4 mc = projected[3 * g], co = projected[3 * g + 1], colour = projected[3 * g + 2];
        s_mean_conic[q] = mc;
        s_conic_opacity[q] = vec4(co.xyz, colour.r);
        s_colour_gb[q] = colour.gb;
        slots[i] = Slot(g);
        // The forward's test (alpha >= min_alpha only where q(d) <= r2) with a wider margin (1.02 instead of
        // 1.01): a superset of the blocks the forward blended the Gaussian on.
        float r2 = -2.0 * (log(min_alpha / co.y) - 1e-3);
        vec2 mean_in_tile = mc.xy - vec2(tile_first_pixel);
        [[unroll]] for (uint b = 0; b < kBlocks; ++b) {
          vec2 b0 = vec2((b % kBlocksX) * kBlockWidth, (b / kBlocksX) * kRows);
          vec2 b1 = b0 + vec2(kBlockWidth - 1, kRows - 1);
          float min_q = MinQuadraticOverRect(b0 - mean_in_tile, b1 - mean_in_tile, mc.z, mc.w, co.x);
          reaches[i][b] = min_q <= 1.02 * r2;
          if (reaches[i][b]) atomicOr(s_block_mask[parity][b][q / 32], 1u << (q % 32));
        }
      }
    }
    barrier();
    // The other parity's masks were read in the previous batch: clear them for the next one.
    if (lid < kBlocks * 2) s_block_mask[parity ^ 1][lid / 2][lid % 2] = 0;
    // The block's Gaussians back to front; pairs at or after the block's end were blended by none of its pixels.
    int block_limit = int(min(n, max(block_end, batch_start) - batch_start));
    [[unroll]] for (int word = 1; word >= 0; --word) {
      uint bits = s_block_mask[parity][block][word] & LowBits(block_limit - 32 * word);
      while (bits != 0) {
        uint bit = uint(findMSB(bits));
        bits &= ~(1u << bit);
        uint k = uint(word) * 32 + bit, pair = batch_start + k;
        vec4 mc = s_mean_conic[k], co = s_conic_opacity[k];
        vec3 colour = vec3(co.w, s_colour_gb[k]);
        float dx = float(px) - mc.x;
        vec2 v_mean = vec2(0.0);
        vec3 v_conic = vec3(0.0), v_colour = vec3(0.0);
        float v_depth = 0.0, v_opacity = 0.0;
        [[unroll]] for (uint j = 0; j < kRows; ++j) {
          // alpha exactly as the forward computed it (same expression), so the same blend decisions.
          float dy = float(py0 + int(j)) - mc.y;
          float power = -0.5 * (mc.z * dx * dx + co.x * dy * dy) - mc.w * dx * dy;
          float G = exp(power), unclamped = co.y * G;
          float alpha = min(max_alpha, unclamped);
          bool blend = pair < end[j] && alpha >= min_alpha;
          T[j] = blend ? T[j] / (1.0 - alpha) : T[j];
          float weight = blend ? T[j] * alpha : 0.0;
          v_colour += weight * v_rgba[j].rgb;
          v_depth += weight * v_D[j];
          float w = dot(v_rgba[j].rgb, colour) + v_rgba[j].a + v_D[j] * co.z;
          float v_alpha = T[j] * (w - S[j]);
          S[j] = blend ? alpha * w + (1.0 - alpha) * S[j] : S[j];
          float v_G = blend && unclamped <= max_alpha ? v_alpha * G : 0.0;  // clamped: no gradient to o, G
          v_opacity += v_G;
          float v_power = v_G * co.y;
          v_conic += v_power * vec3(-0.5 * dx * dx, -dx * dy, -0.5 * dy * dy);
          v_mean += v_power * vec2(mc.z * dx + mc.w * dy, mc.w * dx + co.x * dy);
        }
        v_mean = BlockSum(v_mean);
        v_conic = BlockSum(v_conic);
        v_colour = BlockSum(v_colour);
        v_depth = BlockSum(v_depth);
        v_opacity = BlockSum(v_opacity);
        if (lid % kBlockWidth == 0) {
          s_record[k][block][0] = vec4(v_mean, v_conic.xy);
          s_record[k][block][1] = vec4(v_conic.z, v_depth, v_colour.rg);
          s_record[k][block][2] = vec4(v_colour.b, v_opacity, 0.0, 0.0);
        }
      }
    }
    barrier();
    // Each pair's record: the sum of the records of the blocks that processed it, in block order.
    [[unroll]] for (uint i = 0; i < kLoadsPerInvocation; ++i) {
      uint q = i * kInvocations + lid;
      if (q < n) {
        vec4 record[3] = vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
        [[unroll]] for (uint b = 0; b < kBlocks; ++b) {
          bool processed = reaches[i][b] && batch_start + q < block_ends[b];
          [[unroll]] for (uint r = 0; r < 3; ++r)
            record[r] += processed ? s_record[q][b][r] : vec4(0.0);
        }
        StoreRecord(slots[i], record);
      }
    }
    batch_end = batch_start;
  }
}
