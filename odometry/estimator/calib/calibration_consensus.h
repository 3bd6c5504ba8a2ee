// When a calibration worker locks (docs/METHOD.md, "Online spatiotemporal calibration"): once its latest
// `count` accepted candidates agree, each within a tolerance of their centre, the centre is locked and the
// worker stops. The centre of offsets is their median, that of rotations their chordal mean (the sum of the
// matrices projected onto SO(3)).
#pragma once

#include <optional>
#include <span>

#include "odometry/types/so3.h"

namespace uf::estimator {

// The centre of the last `count` values when they agree within `tolerance` of it; none otherwise (also
// with fewer than `count` values or count < 1).
std::optional<double> OffsetConsensus(std::span<const double> values, int count, double tolerance);
std::optional<SO3> RotationConsensus(std::span<const SO3> values, int count, double tolerance_rad);

}  // namespace uf::estimator
