// Which azimuth convention fits a LiDAR stream whose point times were derived from azimuth
// (odometry/types/azimuth_convention.h)? The convention is a guess about the sensor (spin direction, where
// the sweep starts); a wrong one deskews every scan the wrong way and can make the odometry diverge (a
// handheld Ouster at 2 Hz keyframes: ATE 61 m with KITTI's convention, 0.29 m without deskewing). This
// checks the guess against the data (docs/METHOD.md, "Point times derived from azimuth"):
//
// 1. Motion. The scans are fed as they are read (Add), thinned to one point per thin_voxel_m voxel. A
//    LiDAR-only odometry (the run's lo: settings) runs over them with the current convention. Scan i moves
//    when, between the poses of scans i-1 and i, a point at reference_range_m moves at least
//    min_sweep_motion_m per sweep period T:  (|dt| + |dtheta| r_ref) T / (t_i - t_i-1). Standing still,
//    every convention fits equally, so still scans are dropped until two scans in a row move; the scan
//    before them is kept as the anchor (the odometry maps its first scan as if at rest). A platform that
//    stands is waited for up to max_still_s of stream time.
// 2. Candidates (CandidateConventions). On the anchor and the scans after it (max_scans in all): the
//    current convention, the other direction, for a fixed start also both directions from the other fixed
//    start (behind <-> ahead), and none (no deskew). For each, the times of those scans are derived again
//    and a LiDAR-only LidarOdometry runs over them.
// 3. Score: a point-to-plane residual that does not depend on the estimator's internals. Each scan is
//    deskewed with the candidate's times:
//    - where sweeps touch (each starts where the one before ended), along the trajectory through the
//      odometry's keyframe poses (the scan middles; slerp/lerp between them, their motion extended beyond
//      the ends): one sweep apart, the chord is the motion inside the sweep, and a reversed sweep, which the
//      window's chained nodes cannot absorb, shows;
//    - where they are separate (keyframe data: the median gap from a sweep's end to the next one's start
//      above 1 ms), as the odometry's own begin and end nodes of the sweep place them. Keyframes 0.5 s apart
//      on a hand that turns back and forth: the chord through the middles misses the motion inside the
//      sweep by more than the conventions differ, and not deskewing at all scored best (simulated handheld
//      at 2 Hz, 9 of 10 sequences). The nodes of a separate sweep are free enough to absorb a reversed sweep
//      by trading places, so there the score tells the start and whether to deskew, not the direction.
//    Keyframes are split by parity (the anchor left out); each one's points are compared with the PCA
//    planes (voxel_hash_map.h, the run's lo.map gate) of the keyframes of the other parity (ScoreKeyframes):
//      score = mean over points with a plane of min(|n^T (p - q)|, max_distance_m)
//    A wrong convention warps each scan (a point's pose is taken at the wrong time), which no rigid motion
//    undoes: the scans disagree and the score grows.
// 4. Choice: the lowest score wins, but the current convention is kept unless the winner's score is
//    `margin` (10 %) below its own; and among the candidates the winner is not `margin` below, one that
//    spins in the current convention's direction is taken (what the scores cannot tell stays as read).
//    Fewer than min_scans moving scans: the current one is kept, and the reason says so.
//
// The odometry here is deterministic (its solver time budget is lifted: only the iteration count limits
// it), so the same scans give the same choice.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/types/azimuth_convention.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct PointTimeCheckOptions {
  int max_scans = 12;       // the anchor and the scans after it that the conventions are compared on
  int min_scans = 6;        // moving scans needed among them; fewer: not enough to judge
  // Without motion, Done() once the scans read span this much stream time: a vehicle that waits before it
  // drives (tens of seconds at a start line or a gate) is waited out.
  double max_still_s = 120.0;
  int max_scans_read = 3000;  // and after this many scans in any case (a bound on the work)
  double min_sweep_motion_m =
      0.05;  // a scan moves when a point at reference_range_m moves this much per sweep
  double reference_range_m = 10.0;
  double margin = 0.1;          // another convention wins when its score is this fraction below the current's
  double thin_voxel_m = 0.2;    // scans are held with one point per voxel of this edge (lidar frame), m
  double max_distance_m = 0.5;  // point-to-plane distances are capped here, m

  Status Validate() const;  // "point_time_check.<field>: must be ..., got <value>"
};

struct ConventionScore {
  AzimuthConvention convention;
  double score_m = 0;       // mean capped point-to-plane distance, m
  std::int64_t points = 0;  // points that found a plane
  int keyframes = 0;        // keyframes scored
};

struct PointTimeCheckResult {
  AzimuthConvention current;  // the convention the times came with (kept without a clear winner)
  AzimuthConvention chosen;
  bool compared = false;                // false: not enough motion or scans, chosen = current
  std::vector<ConventionScore> scores;  // the current convention first; empty when not compared
  int scans_read = 0;                   // scans Add was given
  int scans_used = 0;                   // scans the conventions were compared on (anchor included)
  int moving_scans = 0;                 // of those, the ones that moved
  bool separate_sweeps = false;         // of those: keyframes whose sweeps do not touch (step 3)
  double seconds = 0;                   // wall time of Add and Decide together
  // One line: "counter-clockwise from behind: point-to-plane 0.031 m vs clockwise from behind 0.058 m,
  // none (no deskew) 0.040 m over 12 scans".
  std::string reason;
};

class PointTimeCheck {
 public:
  // `config`: the run's LiDAR odometry settings (used LiDAR-only: IMU, wheel and GNSS off, the LiDAR as
  // the body). `current`: the convention the scans' times were derived with.
  static Expected<PointTimeCheck> Create(const LidarOdometryConfig& config, const AzimuthConvention& current,
                                         const PointTimeCheckOptions& options = {});
  PointTimeCheck(PointTimeCheck&&) noexcept;
  PointTimeCheck& operator=(PointTimeCheck&&) noexcept;
  ~PointTimeCheck();

  // The stream's next scan, as read (times derived with `current`). Scans without azimuth-derived times
  // are an error (misuse); empty or out-of-order scans are passed to the odometry, which skips them.
  Status Add(const LidarScan& scan);
  // Enough scans held to compare (max_scans from the anchor), or no motion over max_still_s of stream
  // time, or max_scans_read scans read.
  bool Done() const;
  // Compares the conventions on the scans held (call once, at Done() or at the end of the stream).
  PointTimeCheckResult Decide();

 private:
  struct Impl;
  explicit PointTimeCheck(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The candidates compared for `current` (step 2 above), current first.
std::vector<AzimuthConvention> CandidateConventions(const AzimuthConvention& current);

// Step 3 alone: the score of deskewed scans in the world (in order; the first, the anchor, is left out).
ConventionScore ScoreKeyframes(const std::vector<std::vector<Eigen::Vector3f>>& scans_world,
                               const VoxelMapConfig& map, double max_distance_m);

}  // namespace uf::estimator
