// Forward tile rasterization (render rule 4 of splat/render_types.h): one workgroup per 16x16 tile. The tile is
// split into blocks of 8 x kPixelsPerInvocation pixels, one block per 8 invocations (lavapipe's subgroup);
// lane l of a block shades the pixel column x = l, rows y = 0..kPixelsPerInvocation-1 of the block. The
// tile's depth-sorted Gaussians are loaded in batches of kBatch into shared memory; each pixel blends them
// front to back:
//   alpha = min(max_alpha, opacity exp(-0.5 d^T conic d)), d = pixel - mean_2D; skip if alpha < min_alpha;
//   stop before T (1 - alpha) < cutoff; C += T alpha colour, D += T alpha t_z, T *= 1 - alpha;
//   median depth = t_z where 1 - T first reaches 0.5.
// Exact pruning (why it is fast on lavapipe, whose JIT runs an `if` as a mask over both sides and saves work
// only through loop trip counts): alpha < min_alpha <=> power < ln(min_alpha / opacity), so a Gaussian can
// only be blended at pixels d with q(d) = d^T conic d <= r2, r2 = -2 (ln(min_alpha / opacity) - 1e-3) (the
// 1e-3 margin is far above float rounding; r2 < 0: never). When a batch is loaded, every Gaussian is tested
// against every block (min of q over the block's pixel rectangle <= 1.01 r2, see MinQuadraticOverRect) and
// each block gets a 64-bit mask of the batch's Gaussians that may reach it; the block loops over the set bits
// only, lowest first (= front to back), while one of its pixels is still blending.
// Counted statistic: pixel-Gaussian pairs processed = for every pixel, the tile-list Gaussians it visits
// before it stops (what a 3DGS rasterizer evaluates), including the pruned ones: the list length, or the
// position of the Gaussian that stopped the pixel plus one.
// For the backward (rasterize_backward.comp), per pixel: the final T as float bits and `end` = the absolute
// index of the pair that stopped the pixel (not blended), or the tile's range end: the pixel blended exactly
// the pairs before `end` whose alpha reaches min_alpha.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_control_flow_attributes : require
#include "frame_params.glsl"

const uint kPixelsPerInvocation = 8;                              // rows of a block
const uint kBlockWidth = 8;                                       // columns of a block (one per lane)
const uint kBlocksX = kTileSize / kBlockWidth;                    // 2
const uint kBlocks = kBlocksX * (kTileSize / kPixelsPerInvocation);
const uint kInvocations = kBlocks * kBlockWidth;                  // 32 for 8 rows, 64 for 4
const uint kBatch = 64;                                           // Gaussians per batch: two mask words
const uint kLoadsPerInvocation = kBatch / kInvocations;
layout(local_size_x = kInvocations) in;

layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
layout(std430, binding = 1) readonly buffer Ranges { uvec2 ranges[]; };        // per tile [begin, end)
layout(std430, binding = 2) readonly buffer Values { uint sorted_ids[]; };     // Gaussian index per pair
layout(std430, binding = 3) readonly buffer Projected { vec4 projected[]; };   // see project_gaussians.comp
layout(std430, binding = 4) writeonly buffer Colour { vec4 out_colour[]; };    // per pixel (rgb, alpha)
layout(std430, binding = 5) writeonly buffer Depth { vec2 out_depth[]; };      // per pixel (median, expected)
layout(std430, binding = 6) buffer Counters { uint counters[]; };
layout(std430, binding = 7) writeonly buffer PixelState { uvec2 pixel_state[]; };  // (T bits, end), see above

shared vec4 s_mean_conic[kBatch];       // (u, v, conic a, conic b)
shared vec4 s_conic_opacity[kBatch];    // (conic c, opacity, t_z, colour r)
shared vec2 s_colour_gb[kBatch];        // (colour g, colour b)
shared uint s_block_mask[2][kBlocks][2];  // [batch parity][block][word]: Gaussians whose box meets the block
shared uint s_finished;                 // invocations whose pixels have all stopped

// min over d in [lo, hi] (a box) of q(d) = a dx^2 + 2 b dx dy + c dy^2 (a, c > 0, ac > b^2): 0 when the box
// holds the origin, else the minimum lies on an edge; on the edge dx = x it is at dy = -b x / c (where
// dq/ddy = 0) clamped to the edge, likewise dx = -b y / a on the edge dy = y.
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

void main() {
  uint lid = gl_LocalInvocationID.x;
  uint block = lid / kBlockWidth;
  int width = frame.size.x, height = frame.size.y;
  uvec2 range = ranges[gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x];
  ivec2 tile_first_pixel = ivec2(gl_WorkGroupID.xy * kTileSize);
  ivec2 block_first_pixel =
      tile_first_pixel + ivec2((block % kBlocksX) * kBlockWidth, (block / kBlocksX) * kPixelsPerInvocation);
  int px = block_first_pixel.x + int(lid % kBlockWidth), py0 = block_first_pixel.y;
  float min_alpha = frame.blend.x, max_alpha = frame.blend.y, cutoff = frame.blend.z;
  const float kInf = uintBitsToFloat(0x7f800000u);

  float T[kPixelsPerInvocation], D[kPixelsPerInvocation], median[kPixelsPerInvocation];
  vec3 C[kPixelsPerInvocation];
  bool done[kPixelsPerInvocation];
  uint visited[kPixelsPerInvocation];  // tile-list Gaussians this pixel visits (see the counted statistic)
  bool finished = true;
  [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) {
    T[j] = 1.0;
    D[j] = 0.0;
    median[j] = kInf;
    C[j] = vec3(0.0);
    done[j] = px >= width || py0 + int(j) >= height;  // outside the image: nothing to do
    visited[j] = done[j] ? 0 : range.y - range.x;
    finished = finished && done[j];
  }
  if (lid == 0) s_finished = 0;
  if (lid < kBlocks * 2) s_block_mask[0][lid / 2][lid % 2] = 0;
  barrier();
  if (finished) atomicAdd(s_finished, 1);

  uint parity = 0;
  for (uint batch = range.x; batch < range.y; batch += kBatch, parity ^= 1) {
    barrier();  // the previous batch is consumed; s_finished is stable until the next barrier
    if (s_finished == kInvocations) break;
    // Load: each invocation brings kLoadsPerInvocation Gaussians and marks the blocks their box meets.
    [[unroll]] for (uint i = 0; i < kLoadsPerInvocation; ++i) {
      uint q = i * kInvocations + lid, pair = batch + q;
      if (pair < range.y) {
        uint g = sorted_ids[pair];
        vec4 mc = projected[3 * g], co = projected[3 * g + 1], colour = projected[3 * g + 2];
        s_mean_conic[q] = mc;
        s_conic_opacity[q] = vec4(co.xyz, colour.r);
        s_colour_gb[q] = colour.gb;
        float r2 = -2.0 * (log(min_alpha / co.y) - 1e-3);  // < 0: the Gaussian never reaches min_alpha
        vec2 mean_in_tile = mc.xy - vec2(tile_first_pixel);
        [[unroll]] for (uint b = 0; b < kBlocks; ++b) {
          vec2 b0 = vec2((b % kBlocksX) * kBlockWidth, (b / kBlocksX) * kPixelsPerInvocation);
          vec2 b1 = b0 + vec2(kBlockWidth - 1, kPixelsPerInvocation - 1);
          if (MinQuadraticOverRect(b0 - mean_in_tile, b1 - mean_in_tile, mc.z, mc.w, co.x) <= 1.01 * r2)
            atomicOr(s_block_mask[parity][b][q / 32], 1u << (q % 32));
        }
      }
    }
    barrier();
    // The other parity's masks were read in the previous batch: clear them for the next one.
    if (lid < kBlocks * 2) s_block_mask[parity ^ 1][lid / 2][lid % 2] = 0;
    [[unroll]] for (uint word = 0; word < 2; ++word) {
      uint bits = s_block_mask[parity][block][word];
      // Trip count = Gaussians meeting the block, cut short once every pixel of the block has stopped.
      while (bits != 0 && !finished) {
        uint k = word * 32 + findLSB(bits);
        bits &= bits - 1;
        vec4 mc = s_mean_conic[k], co = s_conic_opacity[k];
        vec3 colour = vec3(co.w, s_colour_gb[k]);
        float dx = float(px) - mc.x;
        [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) {
          float dy = float(py0 + int(j)) - mc.y;
          float power = -0.5 * (mc.z * dx * dx + co.x * dy * dy) - mc.w * dx * dy;
          float alpha = min(max_alpha, co.y * exp(power));
          float next_T = T[j] * (1.0 - alpha);
          bool blend = !done[j] && alpha >= min_alpha;
          bool stop = blend && next_T < cutoff;
          if (stop) visited[j] = batch + k - range.x + 1;
          done[j] = done[j] || stop;
          blend = blend && !stop;
          float weight = blend ? T[j] * alpha : 0.0;
          C[j] += weight * colour;
          D[j] += weight * co.z;
          if (blend && median[j] == kInf && next_T <= 0.5) median[j] = co.z;
          T[j] = blend ? next_T : T[j];
        }
        bool all_done = true;
        [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) all_done = all_done && done[j];
        if (all_done) {
          finished = true;
          atomicAdd(s_finished, 1);
        }
      }
    }
  }

  uint evaluated = 0;
  [[unroll]] for (uint j = 0; j < kPixelsPerInvocation; ++j) {
    evaluated += visited[j];
    int py = py0 + int(j);
    if (px >= width || py >= height) continue;
    uint p = uint(py * width + px);
    float alpha = 1.0 - T[j];
    out_colour[p] = vec4(C[j] + T[j] * frame.background.rgb, alpha);
    out_depth[p] = vec2(median[j], alpha < 1e-4 ? kInf : D[j] / alpha);
    // Inside the image `done` means stopped, at list position visited - 1.
    pixel_state[p] = uvec2(floatBitsToUint(T[j]), done[j] ? range.x + visited[j] - 1 : range.y);
  }

  // Pixel-Gaussian pairs visited: subgroup reduction, one 64-bit (lo, carry) atomic per subgroup.
  uint subgroup_total = subgroupAdd(evaluated);
  if (subgroupElect() && subgroup_total > 0) {
    uint before = atomicAdd(counters[kCounterPixelPairsLo], subgroup_total);
    if (before + subgroup_total < before) atomicAdd(counters[kCounterPixelPairsHi], 1);
  }
}
