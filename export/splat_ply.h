// Gaussian splats in the standard 3DGS PLY layout (Kerbl et al. 2023, as written by the INRIA code and
// read by SuperSplat, Brush and most viewers).
//
// Written: `binary_little_endian 1.0`, one `vertex` element, every property a float, in this order:
//   x y z                        position mu (our world frame, as stored in the model; no axis change)
//   nx ny nz                     zeros (the layout has them; nothing uses them)
//   f_dc_0 f_dc_1 f_dc_2         SH coefficient 0 (DC) of R, G, B
//   f_rest_0 .. f_rest_{3(K-1)-1}  the higher SH coefficients, K = (degree + 1)^2, CHANNEL-major:
//                                f_rest_j is channel c = j / (K - 1), coefficient k = j % (K - 1) + 1,
//                                i.e. all of R's coefficients 1..K-1, then G's, then B's
//                                (the model stores them coefficient-major: sh[i][k * 3 + c])
//   opacity                      the logit, opacity = sigmoid(value)
//   scale_0 scale_1 scale_2      ln(sigma) per local axis
//   rot_0 rot_1 rot_2 rot_3      the quaternion w x y z (stored as in the model, unnormalized)
// A model is validated (GaussianModel::Validate) before anything is written; the file is written under a
// temporary name and renamed. Floats are written as they are, so a write/read round trip is bit-exact.
//
// Read: `ascii 1.0`, `binary_little_endian 1.0` and `binary_big_endian 1.0`; properties in any order, of
// any scalar type (float and double, also integers), converted to float. Required: x y z, f_dc_0..2,
// opacity, scale_0..2, rot_0..3; the error names the first missing one. nx ny nz are optional and unused.
// The SH degree comes from the number of f_rest_N properties: 0, 9, 24, 45 give degree 0, 1, 2, 3, and
// they must be exactly f_rest_0..f_rest_{N-1}; any other count is an error naming it. Other properties
// (e.g. a viewer's extras) are ignored; their names are reported through `ignored_properties` when given.
// The vertex element must be the first element with a non-zero count (compressed layouts, which put a
// `chunk` element first, are rejected with a message saying so); elements after it are not read.
// Values: the model is validated (GaussianModel::Validate, prefixed with the file name), which rejects NaN
// and infinite values, a zero quaternion and log-scales outside [-30, 30]. "Zero or negative scales" cannot
// be told from the file itself: scale_N are logarithms, so negative values are normal (sigma < 1 m); a
// zero linear scale written as log(0) = -inf, or an absurd one, is what gets rejected. A file storing
// linear scales by mistake is indistinguishable from one with Gaussians of e^scale metres.
// Robustness: the vertex count is checked against the file size before anything is allocated (binary: the
// exact record size; ASCII: at least two bytes per value), truncated bodies are errors, the header is
// bounded (1 MiB); bad input gives a Status naming the file and the field, never a crash.
#pragma once

#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "splat/gaussian_model.h"

namespace uf::exporting {

Expected<splat::GaussianModel> ReadSplatPly(const std::string& path,
                                            std::vector<std::string>* ignored_properties = nullptr);

Status WriteSplatPly(const splat::GaussianModel& model, const std::string& path);

}  // namespace uf::exporting
