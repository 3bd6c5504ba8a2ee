// Backward projection (render rules 1-2 of splat/render_types.h backwards; the CPU specification is
// ProjectGaussianBackward in splat/cpu_reference/projection_backward.cpp): per Gaussian of one chunk, the sum
// of its pair gradients (rasterize_backward.comp) chained through the EWA projection, the SH colour and the
// opacity sigmoid to the model parameters. Recomputes the forward's intermediates as project_gaussians.comp.
// Culled Gaussians run the same code and select zero outputs instead of taking an early-out branch: lavapipe
// runs an `if` body masked for every subgroup, and the early-out's zero stores (4 vec4 + the active SH floats,
// each a loop over the lanes) cost every Gaussian; removing it made this stage 20-40 % faster.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "frame_params.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
// Chunk geometry, 3 vec4 per Gaussian: (mu xyz, opacity logit), (log_scale xyz, 0), (quaternion w x y z).
layout(std430, binding = 1) readonly buffer Geometry { vec4 geometry[]; };
layout(std430, binding = 2) readonly buffer Sh { float sh[]; };  // chunk, coefficient-major
layout(std430, binding = 3) readonly buffer Rects { ivec4 rects[]; };        // global; 0 if culled
layout(std430, binding = 4) readonly buffer Offsets { uint offsets[]; };     // global, first pair slot
// 3 vec4 per slot (see rasterize_backward.comp): (u, v, conic a, conic b), (conic c, t_z, r, g), (b, opacity, 0, 0),
// in three pages of S = page_slots slots: slot s is record s - p S of page p = s / S.
layout(std430, binding = 5) readonly buffer PairPage0 { vec4 v_page0[]; };
layout(std430, binding = 8) readonly buffer PairPage1 { vec4 v_page1[]; };
layout(std430, binding = 9) readonly buffer PairPage2 { vec4 v_page2[]; };
// Chunk outputs. v_geometry, 4 vec4 per Gaussian: (dL/dmu xyz, dL/dopacity_logit), (dL/dlog_scale xyz, 0),
// (dL/dq w x y z of the stored quaternion), (dL/d(u, v) summed over pixels, 0, 0). v_sh like sh.
layout(std430, binding = 6) writeonly buffer GeometryGradients { vec4 v_geometry[]; };
layout(std430, binding = 7) writeonly buffer ShGradients { float v_sh[]; };

layout(push_constant) uniform Push {
  uint base;        // global index of the chunk's first Gaussian
  uint count;       // Gaussians in the chunk
  uint page_slots;  // pair records per page
};

const float kC0 = 0.28209479177387814, kC1 = 0.4886025119029199;
const float kC2[5] = float[5](1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
                              0.5462742152960396);
const float kC3[7] = float[7](-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                              -0.4570457994644658, 1.445305721320277, -0.5900435899266435);

// colour_c = sum_k sh_kc Y_k(d): dL/dsh_kc = Y_k dL/dcolour_c; returns dL/dd = sum_k (sum_c sh_kc dL/dcolour_c)
// dY_k/dd, with the partial derivatives of each basis polynomial (same basis as project_gaussians.comp).
vec3 ShBackward(uint first, uint degree, vec3 d, vec3 v_colour, bool culled) {
  float x = d.x, y = d.y, z = d.z;
  float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  float basis[16];
  vec3 grad[16];
  basis[0] = kC0;
  grad[0] = vec3(0.0);
  basis[1] = -kC1 * y;
  grad[1] = vec3(0.0, -kC1, 0.0);
  basis[2] = kC1 * z;
  grad[2] = vec3(0.0, 0.0, kC1);
  basis[3] = -kC1 * x;
  grad[3] = vec3(-kC1, 0.0, 0.0);
  basis[4] = kC2[0] * xy;
  grad[4] = kC2[0] * vec3(y, x, 0.0);
  basis[5] = kC2[1] * yz;
  grad[5] = kC2[1] * vec3(0.0, z, y);
  basis[6] = kC2[2] * (2.0 * zz - xx - yy);
  grad[6] = kC2[2] * vec3(-2.0 * x, -2.0 * y, 4.0 * z);
  basis[7] = kC2[3] * xz;
  grad[7] = kC2[3] * vec3(z, 0.0, x);
  basis[8] = kC2[4] * (xx - yy);
  grad[8] = kC2[4] * vec3(2.0 * x, -2.0 * y, 0.0);
  basis[9] = kC3[0] * y * (3.0 * xx - yy);
  grad[9] = kC3[0] * vec3(6.0 * xy, 3.0 * xx - 3.0 * yy, 0.0);
  basis[10] = kC3[1] * xy * z;
  grad[10] = kC3[1] * vec3(yz, xz, xy);
  basis[11] = kC3[2] * y * (4.0 * zz - xx - yy);
  grad[11] = kC3[2] * vec3(-2.0 * xy, 4.0 * zz - xx - 3.0 * yy, 8.0 * yz);
  basis[12] = kC3[3] * z * (2.0 * zz - 3.0 * xx - 3.0 * yy);
  grad[12] = kC3[3] * vec3(-6.0 * xz, -6.0 * yz, 6.0 * zz - 3.0 * xx - 3.0 * yy);
  basis[13] = kC3[4] * x * (4.0 * zz - xx - yy);
  grad[13] = kC3[4] * vec3(4.0 * zz - 3.0 * xx - yy, -2.0 * xy, 8.0 * xz);
  basis[14] = kC3[5] * z * (xx - yy);
  grad[14] = kC3[5] * vec3(2.0 * xz, -2.0 * yz, xx - yy);
  basis[15] = kC3[6] * x * (xx - 3.0 * yy);
  grad[15] = kC3[6] * vec3(3.0 * xx - 3.0 * yy, -6.0 * xy, 0.0);
  uint n = (degree + 1) * (degree + 1);
  // One pass reading the coefficients (each storage access is a loop over the lanes on lavapipe): the colour
  // and per channel M_c = sum_k sh_kc dY_k/dd, so that dL/dd = sum_c dL/dcolour_c M_c once the clamp is known.
  // Unrolled (constant indices keep basis and grad in registers; a dynamic index would put them in
  // per-lane scratch memory on lavapipe); coefficients past the degree are masked off.
  vec3 colour = vec3(0.0), m_r = vec3(0.0), m_g = vec3(0.0), m_b = vec3(0.0);
  [[unroll]] for (uint k = 0; k < 16; ++k) {
    if (k >= n) break;
    vec3 c = vec3(sh[first + 3 * k], sh[first + 3 * k + 1], sh[first + 3 * k + 2]);
    colour += basis[k] * c;
    m_r += c.r * grad[k];
    m_g += c.g * grad[k];
    m_b += c.b * grad[k];
  }
  // No gradient through a channel clamped at 0 (colour = max(0, SH + 0.5)).
  v_colour = mix(v_colour, vec3(0.0), lessThan(colour + 0.5, vec3(0.0)));
  [[unroll]] for (uint k = 0; k < 16; ++k) {
    if (k >= n) break;
    v_sh[first + 3 * k] = culled ? 0.0 : basis[k] * v_colour.r;
    v_sh[first + 3 * k + 1] = culled ? 0.0 : basis[k] * v_colour.g;
    v_sh[first + 3 * k + 2] = culled ? 0.0 : basis[k] * v_colour.b;
  }
  return v_colour.r * m_r + v_colour.g * m_g + v_colour.b * m_b;
}

// dL/dq of R(q) for a unit quaternion q = (w, x, y, z) given G = dL/dR (G[c][r] = dL/dR_rc), R as in
// project_gaussians.comp (Eigen's toRotationMatrix).
vec4 RotationBackward(vec4 q, mat3 G) {
  float w = q.x, x = q.y, y = q.z, z = q.w;
#define g(r, c) G[c][r]
  return 2.0 * vec4(-z * g(0, 1) + y * g(0, 2) + z * g(1, 0) - x * g(1, 2) - y * g(2, 0) + x * g(2, 1),
                    y * g(0, 1) + z * g(0, 2) + y * g(1, 0) - 2.0 * x * g(1, 1) - w * g(1, 2) + z * g(2, 0) +
                        w * g(2, 1) - 2.0 * x * g(2, 2),
                    -2.0 * y * g(0, 0) + x * g(0, 1) + w * g(0, 2) + x * g(1, 0) + z * g(1, 2) - w * g(2, 0) +
                        z * g(2, 1) - 2.0 * y * g(2, 2),
                    -2.0 * z * g(0, 0) - w * g(0, 1) + x * g(0, 2) + w * g(1, 0) - 2.0 * z * g(1, 1) +
                        y * g(1, 2) + x * g(2, 0) + y * g(2, 1));
#undef g
}

void main() {
  uint local = gl_GlobalInvocationID.x;
  if (local >= count) return;
  uint global_index = base + local;
  // SH: the model's stride; only the coefficients up to the active degree (counts.w) are read and their
  // gradients written. Those above it have zero gradient: the host keeps them zero in v_sh (backward_pass.cpp).
  uint degree = frame.counts.y, stride = 3 * (degree + 1) * (degree + 1);
  uint active_degree = frame.counts.w;
  ivec4 rect = rects[global_index];
  int tiles = (rect.z - rect.x) * (rect.w - rect.y);
  // Culled (no tiles): no gradient. Not an early-out branch: on lavapipe an `if` runs its body masked even
  // when no lane takes it, so the zero stores would cost every Gaussian; instead the culled Gaussian runs
  // the same code (its intermediates may be inf / NaN, e.g. behind the camera) and its outputs are
  // selected 0.
  bool culled = tiles <= 0;
  // Upstream: the sum over the Gaussian's tiles, in tile order: its slots in page 0, then 1, then 2 (each
  // loop reads only its own page; i runs over the page's records).
  vec4 up0 = vec4(0.0), up1 = vec4(0.0), up2 = vec4(0.0);
  uint first_slot = culled ? 0 : offsets[global_index], end_slot = first_slot + uint(max(tiles, 0));
  uint S = page_slots;
  for (uint i = first_slot, e = min(end_slot, S); i < e; ++i) {
    up0 += v_page0[3 * i];
    up1 += v_page0[3 * i + 1];
    up2 += v_page0[3 * i + 2];
  }
  for (uint i = max(first_slot, S) - S, e = clamp(end_slot, S, 2 * S) - S; i < e; ++i) {
    up0 += v_page1[3 * i];
    up1 += v_page1[3 * i + 1];
    up2 += v_page1[3 * i + 2];
  }
  for (uint i = max(first_slot, 2 * S) - 2 * S, e = max(end_slot, 2 * S) - 2 * S; i < e; ++i) {
    up0 += v_page2[3 * i];
    up1 += v_page2[3 * i + 1];
    up2 += v_page2[3 * i + 2];
  }
  vec2 v_uv = up0.xy;
  vec3 v_conic = vec3(up0.zw, up1.x);
  float v_depth = up1.y, v_opacity = up2.y;
  vec3 v_colour = vec3(up1.zw, up2.x);

  // Forward intermediates, as project_gaussians.comp.
  vec4 g0 = geometry[3 * local], g1 = geometry[3 * local + 1], g2 = geometry[3 * local + 2];
  vec3 mu = g0.xyz;
  mat3 W = transpose(mat3(frame.R_row0.xyz, frame.R_row1.xyz, frame.R_row2.xyz));  // R_camera_world
  vec3 t = W * mu + frame.t_camera_world.xyz;
  vec4 q = g2 / length(g2);
  float w = q.x, x = q.y, y = q.z, z = q.w;
  mat3 Rq = mat3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y),
                 2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x),
                 2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y));
  vec3 s = exp(g1.xyz);
  mat3 M = mat3(Rq[0] * s.x, Rq[1] * s.y, Rq[2] * s.z);
  mat3 sigma = M * transpose(M);
  float fx = frame.intrinsics.x, fy = frame.intrinsics.y;
  float lim_x = 1.3 * frame.limits.x, lim_y = 1.3 * frame.limits.y;
  bool clamped_x = abs(t.x / t.z) > lim_x, clamped_y = abs(t.y / t.z) > lim_y;
  float tx = clamp(t.x / t.z, -lim_x, lim_x) * t.z;
  float ty = clamp(t.y / t.z, -lim_y, lim_y) * t.z;
  float tz = t.z, tz2 = tz * tz, tz3 = tz2 * tz;
  mat3 J = mat3(fx / tz, 0.0, 0.0, 0.0, fy / tz, 0.0, -fx * tx / tz2, -fy * ty / tz2, 0.0);  // third row 0
  mat3 T = J * W;
  mat3 cov = T * sigma * transpose(T);
  float a = cov[0][0] + frame.limits.w, b = cov[0][1], c = cov[1][1] + frame.limits.w;
  float det = a * c - b * b;

  // Opacity o = sigmoid(l): do/dl = o (1 - o).
  float opacity = 1.0 / (1.0 + exp(-g0.w));
  float v_logit = v_opacity * opacity * (1.0 - opacity);

  // Colour: SH at d = v / |v|, v = mu - camera centre; dd/dv = (I - d d^T) / |v|.
  vec3 view = mu - frame.centre_world.xyz;
  vec3 d = normalize(view);
  vec3 v_d = ShBackward(local * stride, active_degree, d, v_colour, culled);
  vec3 v_mu = (v_d - d * dot(d, v_d)) / length(view);

  // Conic Q = Sigma_2D^-1 stored (A, B, C); G_Q = [[gA, gB/2], [gB/2, gC]]; G_Sigma2D = -Q G_Q Q.
  mat2 Q = mat2(c / det, -b / det, -b / det, a / det);
  mat2 GQ = mat2(v_conic.x, 0.5 * v_conic.y, 0.5 * v_conic.y, v_conic.z);
  mat2 G2 = -(Q * GQ * Q);
  mat3 G2_3 = mat3(G2[0][0], G2[0][1], 0.0, G2[1][0], G2[1][1], 0.0, 0.0, 0.0, 0.0);
  // Sigma_2D = T Sigma T^T: dL/dSigma = T^T G T, dL/dJ = 2 G T Sigma W^T (rows 0, 1).
  mat3 G_sigma = transpose(T) * G2_3 * T;
  mat3 G_J = 2.0 * G2_3 * T * sigma * transpose(W);
  // J entries: J00 = fx/tz, J11 = fy/tz, J02 = -fx tx'/tz^2 (tx' clamped: then dJ02/dtx = 0, dJ02/dtz =
  // fx tx'/tz^3; else dJ02/dtx = -fx/tz^2, dJ02/dtz = 2 fx tx/tz^3); likewise J12.
  float gJ00 = G_J[0][0], gJ11 = G_J[1][1], gJ02 = G_J[2][0], gJ12 = G_J[2][1];
  vec3 v_t = vec3(0.0);
  v_t.z -= gJ00 * fx / tz2 + gJ11 * fy / tz2;
  if (clamped_x) {
    v_t.z += gJ02 * fx * tx / tz3;
  } else {
    v_t.x -= gJ02 * fx / tz2;
    v_t.z += gJ02 * 2.0 * fx * tx / tz3;
  }
  if (clamped_y) {
    v_t.z += gJ12 * fy * ty / tz3;
  } else {
    v_t.y -= gJ12 * fy / tz2;
    v_t.z += gJ12 * 2.0 * fy * ty / tz3;
  }
  // (u, v) = (fx t_x / t_z + cx, fy t_y / t_z + cy) with the unclamped t; depth t_z.
  v_t.x += v_uv.x * fx / tz;
  v_t.y += v_uv.y * fy / tz;
  v_t.z += -v_uv.x * fx * t.x / tz2 - v_uv.y * fy * t.y / tz2 + v_depth;
  v_mu += transpose(W) * v_t;

  // Sigma = M M^T, M = R S: dL/dM = 2 G_Sigma M, dL/dlog s_k = s_k R_k . (dL/dM)_k, dL/dR = dL/dM S.
  mat3 G_M = 2.0 * G_sigma * M;
  vec3 v_log_scale = s * vec3(dot(Rq[0], G_M[0]), dot(Rq[1], G_M[1]), dot(Rq[2], G_M[2]));
  mat3 G_R = mat3(G_M[0] * s.x, G_M[1] * s.y, G_M[2] * s.z);
  // q_hat = q / |q|: dL/dq = (dL/dq_hat - q_hat (q_hat . dL/dq_hat)) / |q|.
  vec4 g_hat = RotationBackward(q, G_R);
  vec4 v_q = (g_hat - q * dot(q, g_hat)) / length(g2);

  v_geometry[4 * local] = culled ? vec4(0.0) : vec4(v_mu, v_logit);
  v_geometry[4 * local + 1] = culled ? vec4(0.0) : vec4(v_log_scale, 0.0);
  v_geometry[4 * local + 2] = culled ? vec4(0.0) : v_q;
  v_geometry[4 * local + 3] = culled ? vec4(0.0) : vec4(v_uv, 0.0, 0.0);
}
