// What the report lists of the LiDAR window's tracking (lidar_odometry.h, docs/METHOD.md "Registration,
// acceptance and recovery"): a scan whose registration was rejected (it kept its predicted pose and stayed
// out of the map), one registered only from a fallback guess, and a restart of the local map (after repeated
// rejections, or LIO's re-initialization after a divergence): the trajectory is discontinuous there.
#pragma once

#include <string>
#include <string_view>

#include "odometry/types/stamp.h"

namespace uf::estimator {

struct TrackEvent {
  enum class Kind { kRejected, kFallbackGuess, kRestarted };
  Kind kind = Kind::kRejected;
  Stamp stamp = 0;     // of the scan
  std::string detail;  // why, in words
};

std::string_view TrackEventName(TrackEvent::Kind kind);  // "rejected", "fallback guess", "restarted"

}  // namespace uf::estimator
