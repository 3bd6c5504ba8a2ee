// Point times of a spinning LiDAR's scan that carries none, derived from each point's azimuth: the
// conventions as data, and the one derivation that the readers (KITTI-style folders, ROS bags, the
// project's folders) and the check of the conventions (odometry/estimator/point_times/point_time_check.h)
// use.
//
// A spinning LiDAR sweeps its beams around z once per period T. Without a time per point, a point's time is
// guessed from its azimuth a = atan2(y, x) in the LiDAR frame (x forward, y left, z up) and a convention:
//   direction  clockwise seen from above (z up: a decreases with time; Velodyne HDL-64E, the simulator) or
//              counter-clockwise (a increases);
//   start      the azimuth s at which the sweep starts: behind (s = +-pi, KITTI), ahead (s = 0), or the
//              azimuth of the first point stored (a driver that publishes points in firing order);
// and then
//   swept angle  w = s - a (clockwise) or a - s (counter-clockwise), taken into [0, 2 pi)
//   offset       w / (2 pi) * T                                        (ns after the scan stamp)
// Behind: a in (-pi, pi] is one turn already, so w = pi - a (clockwise) or pi + a, in [0, 2 pi], unwrapped.
// First point: the point stored first sweeps w = 0; points of other lasers fired a little before it in the
// same column (a firing offset) sweep "almost 2 pi", points after a whole turn "almost 0". Such a point, one
// within a quarter turn of the seam (w < pi/2 or w > 3 pi/2), is put on the side of the seam that a hint
// says: the point's offset_ns on entry, a guess of its time from its position in the cloud (the reader's;
// or an earlier derivation's, which keeps that side, so the times can be derived again in the other
// direction). In the first half of the period: the sweep's start (w, or 0 for w > 3 pi/2); else its end
// (2 pi for w < pi/2, or w).
// "None" puts every point at the middle of the sweep: the scan is taken as one instant, not deskewed.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "odometry/types/measurements.h"
#include "odometry/types/stamp.h"

namespace uf {

enum class AzimuthSweep { kClockwise, kCounterClockwise, kNone };  // kNone: one instant, no deskew
enum class SweepStart { kBehind, kAhead, kFirstPoint };

struct AzimuthConvention {
  AzimuthSweep sweep = AzimuthSweep::kClockwise;
  SweepStart start = SweepStart::kBehind;  // ignored with AzimuthSweep::kNone

  bool operator==(const AzimuthConvention& other) const {
    return sweep == other.sweep && (sweep == AzimuthSweep::kNone || start == other.start);
  }
};

// KITTI's HDL-64E (see DerivePointTimesFromAzimuth in odometry/io/folders/point_cloud_files.h): the
// KITTI-style folder reader's default.
inline constexpr AzimuthConvention kClockwiseFromBehind{AzimuthSweep::kClockwise, SweepStart::kBehind};
// The ROS bag reader's default: a driver publishes in firing order, from wherever the last scan ended.
inline constexpr AzimuthConvention kClockwiseFromFirstPoint{AzimuthSweep::kClockwise,
                                                            SweepStart::kFirstPoint};
inline constexpr AzimuthConvention kNoDeskew{AzimuthSweep::kNone, SweepStart::kBehind};

// The configuration's word: "clockwise_from_behind", "counter_clockwise_from_ahead",
// "clockwise_from_first_point", ..., "none".
std::string AzimuthConventionKey(const AzimuthConvention& convention);
// Its inverse; nullopt for any other text.
std::optional<AzimuthConvention> ParseAzimuthConvention(std::string_view key);
// In words: "clockwise from behind", "counter-clockwise from the first point", "none (no deskew)".
std::string AzimuthConventionText(const AzimuthConvention& convention);

// The same start in the other direction (clockwise <-> counter-clockwise); none stays none.
AzimuthConvention Reversed(const AzimuthConvention& convention);

// Gives every point of `scan` its offset_ns by `convention` (above) over the sweep [stamp, stamp +
// sweep_period] and sets end = stamp + sweep_period, has_point_times and point_times_from_azimuth. With
// SweepStart::kFirstPoint the offsets on entry are the hints (above), each in [0, sweep_period]. May be
// called again on the same scan with another convention (the hints of the first point survive every
// convention but none). sweep_period > 0.
void DeriveAzimuthPointTimes(LidarScan& scan, Stamp sweep_period, const AzimuthConvention& convention);

}  // namespace uf
