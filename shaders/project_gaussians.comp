// Projection (render rules 1-3 of splat/render_types.h): per Gaussian, EWA splatting of the 3D covariance to a
// 2D conic, the SH colour, the opacity, the pixel radius and the rectangle of touched tiles. One invocation
// per Gaussian of one chunk (the model is uploaded in chunks so that no binding exceeds 128 MiB).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_control_flow_attributes : require
#include "frame_params.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Frame { FrameParams frame; };
// Chunk geometry, 3 vec4 per Gaussian: (mu xyz, opacity logit), (log_scale xyz, 0), (quaternion w x y z).
layout(std430, binding = 1) readonly buffer Geometry { vec4 geometry[]; };
// Chunk SH coefficients, coefficient-major: sh[i * stride + k * 3 + c], stride = 3 (sh_degree + 1)^2.
layout(std430, binding = 2) readonly buffer Sh { float sh[]; };
// Outputs indexed by the global Gaussian index. projected: 3 vec4 per Gaussian:
// (u, v, conic a, conic b), (conic c, opacity, t_z, radius), (r, g, b, 0).
layout(std430, binding = 3) writeonly buffer Projected { vec4 projected[]; };
layout(std430, binding = 4) writeonly buffer Rects { ivec4 rects[]; };  // tiles [x0, x1) x [y0, y1); 0 if culled
layout(std430, binding = 5) writeonly buffer TileCounts { uint tile_counts[]; };
layout(std430, binding = 6) buffer Counters { uint counters[]; };

layout(push_constant) uniform Push {
  uint base;   // global index of the chunk's first Gaussian
  uint count;  // Gaussians in the chunk
};

// SH basis (3DGS constants, same order as splat/cpu_reference/spherical_harmonics.cpp).
vec3 ShColour(uint first, uint degree, vec3 d) {
  const float C0 = 0.28209479177387814, C1 = 0.4886025119029199;
  float basis[16];
  float x = d.x, y = d.y, z = d.z;
  float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  basis[0] = C0;
  basis[1] = -C1 * y;
  basis[2] = C1 * z;
  basis[3] = -C1 * x;
  basis[4] = 1.0925484305920792 * xy;
  basis[5] = -1.0925484305920792 * yz;
  basis[6] = 0.31539156525252005 * (2.0 * zz - xx - yy);
  basis[7] = -1.0925484305920792 * xz;
  basis[8] = 0.5462742152960396 * (xx - yy);
  basis[9] = -0.5900435899266435 * y * (3.0 * xx - yy);
  basis[10] = 2.890611442640554 * xy * z;
  basis[11] = -0.4570457994644658 * y * (4.0 * zz - xx - yy);
  basis[12] = 0.3731763325901154 * z * (2.0 * zz - 3.0 * xx - 3.0 * yy);
  basis[13] = -0.4570457994644658 * x * (4.0 * zz - xx - yy);
  basis[14] = 1.445305721320277 * z * (xx - yy);
  basis[15] = -0.5900435899266435 * x * (xx - 3.0 * yy);
  // Unrolled: constant indices keep basis in registers (a dynamic index puts it in per-lane scratch memory on
  // lavapipe); each coefficient read is a loop over the lanes, so only the active ones are read.
  uint n = (degree + 1) * (degree + 1);
  vec3 colour = vec3(0.0);
  [[unroll]] for (uint k = 0; k < 16; ++k) {
    if (k >= n) break;
    colour += basis[k] * vec3(sh[first + 3 * k], sh[first + 3 * k + 1], sh[first + 3 * k + 2]);
  }
  return colour;
}

// Rule 3: int() of the clamped float equals the clamped truncation and is always defined.
int TileBound(float position_px, int tiles) { return int(clamp(position_px / float(kTileSize), 0.0, float(tiles))); }

bool Project(uint local, uint global_index) {
  vec4 g0 = geometry[3 * local], g1 = geometry[3 * local + 1], g2 = geometry[3 * local + 2];
  vec3 mu = g0.xyz;
  // Rule 1: t = R_cw mu + t_cw; cull in front of the near plane.
  vec3 t = vec3(dot(frame.R_row0.xyz, mu), dot(frame.R_row1.xyz, mu), dot(frame.R_row2.xyz, mu)) +
           frame.t_camera_world.xyz;
  if (t.z < frame.limits.z) return false;

  // Sigma = M M^T, M = R(q) diag(exp(log_scale)), q = (w, x, y, z) normalized.
  vec4 q = g2 / length(g2);
  float w = q.x, x = q.y, y = q.z, z = q.w;
  mat3 Rq = mat3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y),   // column 0
                 2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x),   // column 1
                 2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y));  // column 2
  vec3 s = exp(g1.xyz);
  mat3 M = mat3(Rq[0] * s.x, Rq[1] * s.y, Rq[2] * s.z);
  mat3 sigma = M * transpose(M);

  // EWA: J = [[fx/t_z, 0, -fx t_x/t_z^2], [0, fy/t_z, -fy t_y/t_z^2]] with t_x/t_z, t_y/t_z clamped to 1.3x
  // the half field of view; Sigma_2D = J W Sigma W^T J^T + low_pass I (W = R_camera_world).
  float fx = frame.intrinsics.x, fy = frame.intrinsics.y;
  float lim_x = 1.3 * frame.limits.x, lim_y = 1.3 * frame.limits.y;
  float tx = clamp(t.x / t.z, -lim_x, lim_x) * t.z;
  float ty = clamp(t.y / t.z, -lim_y, lim_y) * t.z;
  mat3 J = mat3(fx / t.z, 0.0, 0.0, 0.0, fy / t.z, 0.0, -fx * tx / (t.z * t.z), -fy * ty / (t.z * t.z), 0.0);
  mat3 W = transpose(mat3(frame.R_row0.xyz, frame.R_row1.xyz, frame.R_row2.xyz));
  mat3 T = J * W;
  mat3 cov = T * sigma * transpose(T);
  float a = cov[0][0] + frame.limits.w, b = cov[0][1], c = cov[1][1] + frame.limits.w;

  // Conic = Sigma_2D^-1; radius = ceil(3 sqrt(lambda_max)), lambda_max = mid + sqrt(mid^2 - det).
  float det = a * c - b * b;
  if (!(det > 0.0)) return false;
  float mid = 0.5 * (a + c);
  float lambda_max = mid + sqrt(max(0.0, mid * mid - det));
  int radius = int(ceil(3.0 * sqrt(lambda_max)));
  if (radius <= 0) return false;

  float u = fx * t.x / t.z + frame.intrinsics.z;
  float v = fy * t.y / t.z + frame.intrinsics.w;
  float r = float(radius);
  ivec4 rect = ivec4(TileBound(u - r, frame.size.z), TileBound(v - r, frame.size.w),
                     TileBound(u + r + float(kTileSize - 1), frame.size.z),
                     TileBound(v + r + float(kTileSize - 1), frame.size.w));
  if (rect.x >= rect.z || rect.y >= rect.w) return false;

  // Rule 2: SH colour at the viewing direction, + 0.5, clamped >= 0; bands above the active degree
  // (counts.w) count as zero.
  uint degree = frame.counts.y;
  uint stride = 3 * (degree + 1) * (degree + 1);
  vec3 colour =
      max(ShColour(local * stride, frame.counts.w, normalize(mu - frame.centre_world.xyz)) + 0.5, 0.0);
  float opacity = 1.0 / (1.0 + exp(-g0.w));

  projected[3 * global_index] = vec4(u, v, c / det, -b / det);
  projected[3 * global_index + 1] = vec4(a / det, opacity, t.z, r);
  projected[3 * global_index + 2] = vec4(colour, 0.0);
  rects[global_index] = rect;
  tile_counts[global_index] = uint((rect.z - rect.x) * (rect.w - rect.y));
  return true;
}

void main() {
  uint local = gl_GlobalInvocationID.x;
  bool visible = false;
  if (local < count) {
    uint global_index = base + local;
    visible = Project(local, global_index);
    if (!visible) {
      rects[global_index] = ivec4(0);
      tile_counts[global_index] = 0;
    }
  }
  // Visible-Gaussian statistic: one atomic per subgroup.
  uint visible_in_subgroup = subgroupBallotBitCount(subgroupBallot(visible));
  if (subgroupElect() && visible_in_subgroup > 0) atomicAdd(counters[kCounterVisible], visible_in_subgroup);
}
