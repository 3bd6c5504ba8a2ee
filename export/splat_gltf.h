// Gaussian splats as binary glTF 2.0 (.glb) with the Khronos extension KHR_gaussian_splatting, read and
// written through tinygltf.
//
// What the specification says (KhronosGroup/glTF, extensions/2.0/Khronos/KHR_gaussian_splatting/README.md;
// read in its 2026 release-candidate text after the editorial review, PR #2567; the published page's status
// is "Complete, Ratified by the Khronos Group"), and what this file does with it:
//  - "The `mode` property of the mesh primitive MUST be `POINTS` (0)." -> one POINTS primitive.
//  - The primitive's extension object: `kernel` (required; only "ellipse" is defined), `colorSpace`
//    (required; "srgb_rec709_display": "BT.709 sRGB (display-referred)" or "lin_rec709_display"),
//    `projection` (default "perspective"), `sortingMethod` (default "cameraDistance"). Written: "ellipse",
//    "srgb_rec709_display" (our colours are display-referred sRGB, gaussian_model.h), "perspective",
//    "cameraDistance" (the only defined value; our renderer sorts by view depth t_z, which the spec does
//    not name). The extension is listed in extensionsUsed, not extensionsRequired (points are a fallback).
//  - Attributes: POSITION (VEC3); KHR_gaussian_splatting:ROTATION (VEC4) "stored as unit quaternions in
//    the usual glTF order" (x, y, z, w); KHR_gaussian_splatting:SCALE (VEC3) "Scale values are linear and
//    MUST NOT be negative" (sigma = exp(log_scale)); KHR_gaussian_splatting:OPACITY (SCALAR) "a normalized
//    linear value between 0.0 (transparent) and 1.0 (opaque)" (sigmoid(logit)); SH_DEGREE_0_COEF_0 (VEC3,
//    float, required) and KHR_gaussian_splatting:SH_DEGREE_l_COEF_n for l = 1..3, n = 0..2l (VEC3, float),
//    "packed from the lowest order (m) to highest for each degree", so COEF_n is m = n - l, which is the
//    3DGS coefficient k = l^2 + n; lower degrees MUST be present and degrees MUST NOT be partial. The SH
//    basis and the 0.5 bias are the 3DGS ones (colour = SH_0,0 * 0.2820947917738781 + ... + 0.5).
//  - COLOR_0 is optional ("MAY be used") as a point-cloud fallback: "multiplying ... by 0.282095, adding
//    0.5, and clamping ... to [0, 1]; if the color space is srgb_rec709_display, the clamped values would
//    have to be decoded from sRGB to linear" (COLOR_0 is linear), alpha "SHOULD contain the opacity".
//    Written: COLOR_0 as float VEC4 linear RGB + opacity. Ignored when reading.
//  - Node transforms apply to the splats (positions, covariance "Sigma = M C C^T M^T", and the SH "SHOULD
//    be transformed by the rotation component"); the spec recommends data in the glTF coordinate system.
// Frames: glTF is y-up, our world z-up. Written data is converted, (x, y, z)_gltf = (x, z, -y)_ours (a -90
// deg rotation R about x, as in gltf_writer.h): positions p' = R p, rotations q' = q_R q, SH rotated by R
// (sh_rotation.h); the node has no transform. Reading undoes this and first applies each node's global
// transform (translation, rotation, uniform positive scale; non-uniform or negative scales are errors).
// Precision: positions convert exactly; scale (exp/log) and opacity (sigmoid/logit) round trips are exact up
// to float rounding of the stored linear value (opacity is clamped to [1e-9, 1 - 1e-9] before the logit, so
// logits beyond about +-16.6 come back as the logit of the nearest float below 1); quaternions are written
// normalized; SH and quaternions pick up ~1e-7 relative error from the rotation.
// Reading accepts the component types the spec lists (float, normalized (u)byte/(u)short, and unnormalized
// ubyte/ushort for SCALE), interleaved views, several splat primitives and nodes (merged, missing SH
// degrees zero), .glb and .gltf; it rejects sparse accessors, required extensions it does not know (e.g.
// compression), colour spaces other than srgb_rec709_display (lin_rec709_display would need a non-linear
// conversion of view-dependent colour), out-of-range accessors and counts, and then validates the model.
#pragma once

#include <string>

#include "odometry/types/status.h"
#include "splat/gaussian_model.h"

namespace uf::exporting {

inline constexpr const char* kGaussianSplattingExtension = "KHR_gaussian_splatting";

Status WriteSplatGlb(const splat::GaussianModel& model, const std::string& path);

Expected<splat::GaussianModel> ReadSplatGltf(const std::string& path);  // .glb or .gltf

}  // namespace uf::exporting
