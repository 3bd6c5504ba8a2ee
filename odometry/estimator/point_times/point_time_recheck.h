// The point-time convention checked again when the registration degrades (docs/METHOD.md "Point times
// derived from azimuth"). The check at the start (point_time_check.h) judges the first moving scans; a drive
// whose start does not tell the conventions apart keeps the reader's guess, and a wrong guess shows later,
// where the motion is larger, as registrations that fail. So during the run:
//
// - the first scan whose registration was rejected, or the first restart of the local map (TrackEvent),
//   starts a PointTimeCheck with the run's lo: settings and the convention the run derives with;
// - the scans read from then on go to it as read, until it is Done (its anchor and max_scans scans after
//   the first motion), and it decides;
// - when it chooses another convention, every later scan's times are derived again with that one before the
//   odometry gets it (the scans before keep theirs: their poses are in the window and the map already).
//
// Once per run: a second degradation does not check again (the first answer stands).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/estimator/lidar_odometry/track_event.h"
#include "odometry/estimator/point_times/point_time_check.h"
#include "odometry/types/azimuth_convention.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct PointTimeRecheckResult {
  TrackEvent trigger;                  // the event that started the check
  PointTimeCheckResult check;          // its decision (check.current: the convention the run derived with)
  std::optional<Stamp> switched_from;  // the first scan whose times were derived with check.chosen; none:
                                       //   the convention was kept (or no scan came after the decision)
  // One line for the report: "re-checked after the scan rejected at 12.300000 s: <reason>; from the scan at
  // 14.000000 s on, the times are derived clockwise from ahead".
  std::string Line() const;
};

class PointTimeRecheck {
 public:
  // `config`: the run's LiDAR odometry settings; `current`: the convention the run's scans are derived with.
  static Expected<PointTimeRecheck> Create(const LidarOdometryConfig& config,
                                           const AzimuthConvention& current,
                                           const PointTimeCheckOptions& options = {});

  // The track's events so far (in order; a prefix of the next call's): the first rejection or restart starts
  // the check.
  void Notice(const std::vector<TrackEvent>& events);
  // The next scan of the stream, before the odometry gets it: while the check runs, a thinned copy goes to
  // it; once another convention was chosen, the scan's times are derived again with that one. Errors: the
  // check's (a scan without azimuth times).
  Status Prepare(LidarScan& scan);
  // At the end of the stream: a check still running decides on what it holds.
  void Finish();

  // Set once the check decided.
  const std::optional<PointTimeRecheckResult>& result() const { return result_; }

 private:
  PointTimeRecheck(LidarOdometryConfig config, AzimuthConvention current, PointTimeCheckOptions options)
      : config_(std::move(config)), current_(current), options_(options) {}
  void Decide();

  LidarOdometryConfig config_;
  AzimuthConvention current_;
  PointTimeCheckOptions options_;
  std::size_t events_seen_ = 0;
  std::optional<TrackEvent> trigger_;
  std::optional<PointTimeCheck> check_;  // while it runs
  std::optional<PointTimeRecheckResult> result_;
};

}  // namespace uf::estimator
