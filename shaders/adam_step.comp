// One Adam step (Kingma & Ba 2015) on one chunk of the model, in place, plus the 3DGS densification
// statistics (the CPU specification is AdamStepReference in splat/training/adam_reference.cpp). Per
// parameter p with gradient g, bias corrections c1 = 1 - b1^t, c2 = 1 - b2^t (computed by the host):
//   m = b1 m + (1 - b1) g,  v = b2 v + (1 - b2) g^2,  p -= lr (m / c1) / (sqrt(v / c2) + eps).
// One dispatch per chunk, one invocation per Gaussian doing both parameter groups:
//   geometry: its 3 vec4 (mu, opacity logit), (log_scale, -), (raw quaternion w x y z); then, when the
//     Gaussian was seen this frame (tile count > 0), adds |dL/d(mean in NDC)| = |(dL/du W/2, dL/dv H/2)| to its
//     accumulator, 1 to its view count and keeps the largest screen radius;
//   SH (coefficient-major, 3 floats per coefficient): coefficient 0 at the DC rate, 1 .. active - 1 at the
//     rest rate, the others untouched (parameter and moments).
// The step is skipped as a whole (nothing written) when the forward of the same submission had more
// tile-Gaussian pairs than key slots (counters[0] > pair_capacity): its images, and so the gradients, are
// incomplete; the host then grows the key buffers and records the iteration again.
// Lavapipe speed (measured at 100k Gaussians, degree 3): one invocation per Gaussian, not per float
// (invocations cost more than the update), and vec4 loads / stores where the layout allows (geometry; SH of
// degree 1 and 3) cut the time ~6x. Grid-stride loops over a few big workgroups. On lavapipe an `if` runs both
// of its sides (masked), even on a uniform condition, while a loop whose trip count is 0 for every lane is
// skipped: so geometry and SH are one dispatch (no per-mode branch: each dispatch used to run the other mode's
// loads masked off, and twice the invocations), and the vec4 / scalar SH variants are loops with host-computed
// trip counts (sh_vec4s, sh_scalars), one of them 0, instead of an if / else: ~30 % faster than the former two
// dispatches per chunk (100k Gaussians, active degree 0).
#version 460
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x = 256) in;

// Chunk geometry (3 vec4 per Gaussian), its moments (same layout) and its gradients (4 vec4 per Gaussian:
// (dL/dmu, dL/dopacity_logit), (dL/dlog_scale, 0), (dL/dq w x y z), (dL/d(u, v), 0, 0)).
layout(std430, binding = 0) buffer GeometryParams { vec4 gp[]; };
layout(std430, binding = 1) buffer GeometryFirstMoments { vec4 gm[]; };
layout(std430, binding = 2) buffer GeometrySecondMoments { vec4 gv[]; };
layout(std430, binding = 3) readonly buffer GeometryGradients { vec4 gg[]; };
// Chunk SH, its moments and its gradients (all like the model's SH), as floats and as vec4 (aliases; the
// vec4 view is used when the SH stride is a multiple of 4).
layout(std430, binding = 4) buffer ShParams { float sp[]; };
layout(std430, binding = 5) buffer ShFirstMoments { float sm[]; };
layout(std430, binding = 6) buffer ShSecondMoments { float sv[]; };
layout(std430, binding = 7) readonly buffer ShGradients { float sg[]; };
layout(std430, binding = 4) buffer ShParams4 { vec4 sp4[]; };
layout(std430, binding = 5) buffer ShFirstMoments4 { vec4 sm4[]; };
layout(std430, binding = 6) buffer ShSecondMoments4 { vec4 sv4[]; };
layout(std430, binding = 7) readonly buffer ShGradients4 { vec4 sg4[]; };
layout(std430, binding = 8) readonly buffer TileCounts { uint tile_counts[]; };  // global index; > 0: seen
// Chunk statistics, 3 per Gaussian: gradient accumulator (float bits), view count, max radius (float bits).
layout(std430, binding = 9) buffer Statistics { uint stats[]; };
// The forward's projected Gaussians (global index, 3 vec4; the radius in px is .w of the second).
layout(std430, binding = 10) readonly buffer Projected { vec4 projected[]; };
// The forward's counters ([0]: tile-Gaussian pairs of the frame).
layout(std430, binding = 11) readonly buffer Counters { uint counters[]; };

layout(push_constant) uniform Push {
  uint sh_vec4s;       // vec4 loop trip count: ceil(active_floats / 4) when sh_stride % 4 == 0, else 0
  uint count;          // Gaussians in the chunk
  uint base;           // global index of the chunk's first Gaussian
  uint sh_stride;      // SH floats per Gaussian
  uint active_floats;  // 3 x active SH coefficients
  uint sh_scalars;     // scalar loop trip count: active_floats when sh_stride % 4 != 0, else 0
  uint has_projected;  // 1: binding 10 holds the projected Gaussians (max radius), 0: ignore it
  float beta1, beta2, epsilon, c1, c2;
  float lr_position, lr_log_scale, lr_rotation, lr_opacity, lr_sh_dc, lr_sh_rest;
  float ndc_scale_x, ndc_scale_y;
  uint pair_capacity;  // key slots of the forward; 0xffffffff: no check
};

// The update of one value; the SH's scalar path.
float AdamValue(inout float m1, inout float v1, float p, float gradient, float lr) {
  m1 = beta1 * m1 + (1.0 - beta1) * gradient;
  v1 = beta2 * v1 + (1.0 - beta2) * (gradient * gradient);
  return p - lr * (m1 / c1) / (sqrt(v1 / c2) + epsilon);
}
void AdamSh(uint e, float lr) {
  float m1 = sm[e], v1 = sv[e];
  float p1 = AdamValue(m1, v1, sp[e], sg[e], lr);
  sm[e] = m1;
  sv[e] = v1;
  sp[e] = p1;
}

// The same on 4 values at once (p, m, v updated in place); components where `live` is false keep theirs.
void Adam4(inout vec4 p0, inout vec4 m0, inout vec4 v0, vec4 gradient, vec4 lr, bvec4 live) {
  vec4 m1 = beta1 * m0 + (1.0 - beta1) * gradient;
  vec4 v1 = beta2 * v0 + (1.0 - beta2) * (gradient * gradient);
  vec4 p1 = p0 - lr * (m1 / c1) / (sqrt(v1 / c2) + epsilon);
  m0 = mix(m0, m1, live);
  v0 = mix(v0, v1, live);
  p0 = mix(p0, p1, live);
}

void GeometryStep(uint k) {
  const bvec4 all_live = bvec4(true);
  const vec4 lr[3] = vec4[3](vec4(vec3(lr_position), lr_opacity), vec4(lr_log_scale), vec4(lr_rotation));
  const bvec4 live[3] = bvec4[3](all_live, bvec4(true, true, true, false), all_live);  // log_scale .w unused
  [[unroll]] for (uint r = 0; r < 3; ++r) {
    uint e = 3 * k + r;
    vec4 p = gp[e], m = gm[e], v = gv[e];
    Adam4(p, m, v, gg[4 * k + r], lr[r], live[r]);
    gp[e] = p;
    gm[e] = m;
    gv[e] = v;
  }
  uint i = base + k;
  if (tile_counts[i] == 0) return;
  vec2 ndc_gradient = gg[4 * k + 3].xy * vec2(ndc_scale_x, ndc_scale_y);
  stats[3 * k] = floatBitsToUint(uintBitsToFloat(stats[3 * k]) + length(ndc_gradient));
  stats[3 * k + 1] += 1;
  if (has_projected != 0)
    stats[3 * k + 2] = floatBitsToUint(max(uintBitsToFloat(stats[3 * k + 2]), projected[3 * i + 1].w));
}

// The SH of Gaussian k: only its active coefficients (the others keep their values and moments).
void ShStep(uint k) {
  uint first = k * sh_stride;
  // Degrees 1 and 3 (12, 48 floats): whole vec4s, float f of the Gaussian's SH at the DC rate when f < 3
  // and masked off when f >= 3 x active coefficients.
  uint first4 = first / 4;
  for (uint q = 0; q < sh_vec4s; ++q) {
    uvec4 index = uvec4(4 * q) + uvec4(0, 1, 2, 3);
    vec4 lr = mix(vec4(lr_sh_rest), vec4(lr_sh_dc), lessThan(index, uvec4(3)));
    uint e = first4 + q;
    vec4 p = sp4[e], m = sm4[e], v = sv4[e];
    Adam4(p, m, v, sg4[e], lr, lessThan(index, uvec4(active_floats)));
    sp4[e] = p;
    sm4[e] = m;
    sv4[e] = v;
  }
  // Degrees 0 and 2: float by float.
  for (uint j = 0; j < sh_scalars; ++j) AdamSh(first + j, j < 3 ? lr_sh_dc : lr_sh_rest);
}

void main() {
  if (counters[0] > pair_capacity) return;
  uint total = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint j = gl_GlobalInvocationID.x; j < count; j += total) {
    GeometryStep(j);
    ShStep(j);
  }
}
