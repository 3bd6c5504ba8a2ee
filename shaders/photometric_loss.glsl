// Shared by the photometric_loss_*.comp shaders (the photometric training loss on the device; the CPU
// specification is EvaluatePhotometricLoss in splat/cpu_reference/photometric_loss.h, the host side
// splat/vk/loss_pass.cpp). Every stage runs one workgroup per band of kBandRows image rows (few big
// workgroups, as lavapipe likes: a workgroup is one CPU thread), 64 invocations.
//
// SSIM window: 11 taps g_k = exp(-k^2 / (2 1.5^2)) / sum, k = -5..5 (SsimWindow() in
// splat/training/image_metrics.h); blurs are zero padded: taps outside the image count as 0.
//
// Speed on lavapipe: a storage-buffer load at a per-lane address costs a loop over the lanes, so the blurs
// are register-blocked: a row blur invocation owns a run of kRun consecutive pixels of a row and loads its
// kRun + 10 inputs once; a column blur invocation owns the kBandRows pixels of one column of the band and
// loads its kBandRows + 10 inputs once (the tap loops are unrolled, the arrays stay in registers / stack).
// Out-of-image taps load a clamped address and are multiplied by 0 (no divergent branches).
layout(local_size_x = 64) in;
const int kBandRows = 16;
const int kRun = 16;  // pixels per invocation of a row blur
const int kRadius = 5;
const float kWindow[11] = float[11](0.00102838008447911, 0.007598758135239185, 0.03600077212843083,
                                    0.10936068950970002, 0.2130055377112537, 0.26601172486179436,
                                    0.2130055377112537, 0.10936068950970002, 0.03600077212843083,
                                    0.007598758135239185, 0.00102838008447911);
const float kC1 = 0.0001, kC2 = 0.0009;  // 0.01^2, 0.03^2
const uint kMaxSubgroups = 16;  // 64 invocations in subgroups of >= 4 lanes
// The partial sums: per band and subgroup kPartialWords words (sum S, sum |r - t|, sum |E - d| / d as float
// bits, and the number of depth pairs), at (band kMaxSubgroups + subgroup) kPartialWords; the host zeroes the
// buffer first (slots of subgroups that do not exist stay 0) and adds them all in double. Per-subgroup sums
// need no barrier(): on lavapipe a shader with barriers runs as coroutines, several times slower here.
const uint kPartialWords = 4;

layout(push_constant) uniform Push {
  int width;
  int height;
  float ssim_weight;   // l of L = (1 - l) L1 + l (1 - SSIM) + w_d L_depth
  float depth_weight;  // w_d
};

// The rows [FirstRow(), EndRow()) of this workgroup's band.
int FirstRow() { return int(gl_WorkGroupID.x) * kBandRows; }
int EndRow() { return min(height, FirstRow() + kBandRows); }

// Where this subgroup's `word` of its band goes.
uint PartialSlot(uint word) { return (gl_WorkGroupID.x * kMaxSubgroups + gl_SubgroupID) * kPartialWords + word; }

// A target depth below 0 marks a masked pixel (LossPass::kMaskedDepth): the rendered rgb counts as the
// target's there (no loss, no gradient). Returns 1 for a masked pixel, else 0.
float Masked(float target_depth) { return target_depth < 0.0 ? 1.0 : 0.0; }

// Whether pixel p has a depth pair: target depth > 0 and rendered alpha >= 1e-4 (expected depth defined).
bool HasDepthPair(float target_depth, float alpha, float expected_depth) {
  return target_depth > 0.0 && alpha >= 1e-4 && !isinf(expected_depth) && !isnan(expected_depth);
}

// The 15 moment values of a pixel (x, y, x^2, y^2, xy for rgb; x rendered, y target) packed into 4 vec4
// (blurs are linear, so the packed vectors are blurred as they are): (x.rgb, y.r), (y.gb, xx.rg),
// (xx.b, yy.rgb), (xy.rgb, 0). Intermediate maps are vec4 arrays: on lavapipe a load or store costs a loop
// over the lanes per instruction, a vec4 costs about what a float does.
void PackMoments(vec3 x, vec3 y, out vec4 m[4]) {
  vec3 xx = x * x, yy = y * y, xy = x * y;
  m[0] = vec4(x, y.r);
  m[1] = vec4(y.gb, xx.rg);
  m[2] = vec4(xx.b, yy);
  m[3] = vec4(xy, 0.0);
}
void UnpackMoments(vec4 m[4], out vec3 mx, out vec3 my, out vec3 mxx, out vec3 myy, out vec3 mxy) {
  mx = m[0].xyz;
  my = vec3(m[0].w, m[1].xy);
  mxx = vec3(m[1].zw, m[2].x);
  myy = m[2].yzw;
  mxy = m[3].xyz;
}
