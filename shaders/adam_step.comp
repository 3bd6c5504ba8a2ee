// One Adam step (Kingma & Ba 2015) on one chunk of the model, in place, plus the 3DGS densification
// statistics (the CPU specification is AdamStepReference in splat/training/adam_reference.cpp). Per
// parameter p with gradient g, bias corrections c1 = 1 - b1^t, c2 = 1 - b2^t (computed by the host):
//   m = b1 m + (1 - b1) g,  v = b2 v + (1 - b2) g^2,  p -= lr (m / c1) / (sqrt(v / c2) + eps).
// Two modes, dispatched once each per chunk (independent, no barrier between them):
//   mode 0, geometry: one invocation per Gaussian over its 3 vec4 (mu, opacity logit), (log_scale, -),
//     (raw quaternion w x y z); then, when the Gaussian was seen this frame (tile count > 0), adds
//     |dL/d(mean in NDC)| = |(dL/du W/2, dL/dv H/2)| to its accumulator, 1 to its view count and keeps the
//     largest screen radius.
//   mode 1, SH: one invocation per Gaussian over its SH (coefficient-major, 3 floats per coefficient):
//     coefficient 0 at the DC rate, 1 .. active - 1 at the rest rate, the others untouched (parameter and
//     moments).
// The step is skipped as a whole (nothing written) when the forward of the same submission had more
// tile-Gaussian pairs than key slots (counters[0] > pair_capacity): its images, and so the gradients, are
// incomplete; the host then grows the key buffers and records the iteration again.
// Lavapipe speed (measured at 100k Gaussians, degree 3): one invocation per Gaussian, not per float
// (invocations cost more than the update), and vec4 loads / stores where the layout allows (geometry; SH of
// degree 1 and 3) cut the time ~6x. Grid-stride loops over a few big workgroups.
#version 460

layout(local_size_x = 256) in;

// Mode 0: chunk geometry (12 floats per Gaussian), its moments (same layout) and its gradients (16 floats
// per Gaussian: (dL/dmu, dL/dopacity_logit), (dL/dlog_scale, 0), (dL/dq w x y z), (dL/d(u, v), 0, 0)).
// Mode 1: chunk SH, its moments and its gradients (all like the model's SH).
layout(std430, binding = 0) buffer Params { float params[]; };
layout(std430, binding = 1) buffer FirstMoments { float m[]; };
layout(std430, binding = 2) buffer SecondMoments { float v[]; };
layout(std430, binding = 3) readonly buffer Gradients { float g[]; };
// The same SH buffers as vec4 (aliases of bindings 0-3; used when the SH stride is a multiple of 4).
layout(std430, binding = 0) buffer Params4 { vec4 params4[]; };
layout(std430, binding = 1) buffer FirstMoments4 { vec4 m4[]; };
layout(std430, binding = 2) buffer SecondMoments4 { vec4 v4[]; };
layout(std430, binding = 3) readonly buffer Gradients4 { vec4 g4[]; };
layout(std430, binding = 4) readonly buffer TileCounts { uint tile_counts[]; };  // global index; > 0: seen
// Chunk statistics, 3 per Gaussian: gradient accumulator (float bits), view count, max radius (float bits).
layout(std430, binding = 5) buffer Statistics { uint stats[]; };
// The forward's projected Gaussians (global index, 3 vec4; the radius in px is .w of the second).
layout(std430, binding = 6) readonly buffer Projected { vec4 projected[]; };
// The forward's counters ([0]: tile-Gaussian pairs of the frame).
layout(std430, binding = 7) readonly buffer Counters { uint counters[]; };

layout(push_constant) uniform Push {
  uint mode;           // 0 geometry, 1 SH
  uint count;          // Gaussians in the chunk
  uint base;           // global index of the chunk's first Gaussian
  uint sh_stride;      // SH floats per Gaussian
  uint active_floats;  // 3 x active SH coefficients
  uint has_projected;  // 1: binding 6 holds the projected Gaussians (max radius), 0: ignore it
  float beta1, beta2, epsilon, c1, c2;
  float lr_position, lr_log_scale, lr_rotation, lr_opacity, lr_sh_dc, lr_sh_rest;
  float ndc_scale_x, ndc_scale_y;
  uint pair_capacity;  // key slots of the forward; 0xffffffff: no check
};

void Adam(uint e, float gradient, float lr) {
  float m1 = beta1 * m[e] + (1.0 - beta1) * gradient;
  float v1 = beta2 * v[e] + (1.0 - beta2) * (gradient * gradient);
  m[e] = m1;
  v[e] = v1;
  params[e] -= lr * (m1 / c1) / (sqrt(v1 / c2) + epsilon);
}

// The same on 4 parameters at once; components where `live` is false keep their parameter and moments.
void Adam4(uint e, vec4 gradient, vec4 lr, bvec4 live) {
  vec4 m0 = m4[e], v0 = v4[e], p0 = params4[e];
  vec4 m1 = beta1 * m0 + (1.0 - beta1) * gradient;
  vec4 v1 = beta2 * v0 + (1.0 - beta2) * (gradient * gradient);
  vec4 p1 = p0 - lr * (m1 / c1) / (sqrt(v1 / c2) + epsilon);
  m4[e] = mix(m0, m1, live);
  v4[e] = mix(v0, v1, live);
  params4[e] = mix(p0, p1, live);
}

void GeometryStep(uint k) {
  const bvec4 all_live = bvec4(true);
  Adam4(3 * k, g4[4 * k], vec4(vec3(lr_position), lr_opacity), all_live);
  Adam4(3 * k + 1, g4[4 * k + 1], vec4(lr_log_scale), bvec4(true, true, true, false));  // .w unused
  Adam4(3 * k + 2, g4[4 * k + 2], vec4(lr_rotation), all_live);
  uint i = base + k;
  if (tile_counts[i] == 0) return;
  vec2 ndc_gradient = g4[4 * k + 3].xy * vec2(ndc_scale_x, ndc_scale_y);
  stats[3 * k] = floatBitsToUint(uintBitsToFloat(stats[3 * k]) + length(ndc_gradient));
  stats[3 * k + 1] += 1;
  if (has_projected != 0)
    stats[3 * k + 2] = floatBitsToUint(max(uintBitsToFloat(stats[3 * k + 2]), projected[3 * i + 1].w));
}

// The SH of Gaussian k: only its active coefficients (the others keep their values and moments).
void ShStep(uint k) {
  uint first = k * sh_stride;
  if (sh_stride % 4 == 0) {
    // Degrees 1 and 3 (12, 48 floats): whole vec4s, float f of the Gaussian's SH at the DC rate when f < 3
    // and masked off when f >= 3 x active coefficients.
    uint first4 = first / 4;
    for (uint q = 0; 4 * q < active_floats; ++q) {
      uvec4 index = uvec4(4 * q) + uvec4(0, 1, 2, 3);
      vec4 lr = mix(vec4(lr_sh_rest), vec4(lr_sh_dc), lessThan(index, uvec4(3)));
      Adam4(first4 + q, g4[first4 + q], lr, lessThan(index, uvec4(active_floats)));
    }
    return;
  }
  for (uint c = 0; c < 3; ++c) Adam(first + c, g[first + c], lr_sh_dc);
  for (uint j = 3; j < active_floats; ++j) Adam(first + j, g[first + j], lr_sh_rest);
}

void main() {
  if (counters[0] > pair_capacity) return;
  uint total = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint j = gl_GlobalInvocationID.x; j < count; j += total) {
    if (mode == 0)
      GeometryStep(j);
    else
      ShStep(j);
  }
}
