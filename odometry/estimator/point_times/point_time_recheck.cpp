#include "odometry/estimator/point_times/point_time_recheck.h"

namespace uf::estimator {

std::string PointTimeRecheckResult::Line() const {
  std::string line = "re-checked after the " +
                     std::string(trigger.kind == TrackEvent::Kind::kRestarted ? "restart of the local map"
                                                                              : "scan rejected") +
                     " at " + StampText(trigger.stamp) + ": " + check.reason;
  if (switched_from)
    line += "; from the scan at " + StampText(*switched_from) + " on, the times are derived " +
            AzimuthConventionText(check.chosen);
  else if (check.chosen != check.current)
    line += "; no scan came after the decision";
  return line;
}

Expected<PointTimeRecheck> PointTimeRecheck::Create(const LidarOdometryConfig& config,
                                                    const AzimuthConvention& current,
                                                    const PointTimeCheckOptions& options) {
  // The check's own errors (options, odometry settings) surface here rather than at the first degradation.
  if (Expected<PointTimeCheck> trial = PointTimeCheck::Create(config, current, options); !trial)
    return trial.status();
  return PointTimeRecheck(config, current, options);
}

void PointTimeRecheck::Notice(const std::vector<TrackEvent>& events) {
  for (; events_seen_ < events.size(); ++events_seen_) {
    const TrackEvent& event = events[events_seen_];
    if (trigger_ || event.kind == TrackEvent::Kind::kFallbackGuess) continue;
    trigger_ = event;
    Expected<PointTimeCheck> check = PointTimeCheck::Create(config_, current_, options_);
    if (check) check_.emplace(std::move(*check));  // Create checked these settings once already
  }
}

Status PointTimeRecheck::Prepare(LidarScan& scan) {
  if (check_) {
    if (Status s = check_->Add(scan); !s.ok()) return s;
    if (check_->Done()) Decide();
    return {};
  }
  if (!result_ || result_->check.chosen == result_->check.current) return {};
  if (!result_->switched_from) result_->switched_from = scan.stamp;
  DeriveAzimuthPointTimes(scan, scan.end - scan.stamp, result_->check.chosen);
  return {};
}

void PointTimeRecheck::Finish() {
  if (check_) Decide();
}

void PointTimeRecheck::Decide() {
  result_ = PointTimeRecheckResult{*trigger_, check_->Decide(), std::nullopt};
  check_.reset();
}

}  // namespace uf::estimator
