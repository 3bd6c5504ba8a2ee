// The camera's part of the reliability scheduling (visual_provider.h; docs/METHOD.md "Factor-wise
// reliability scheduling", camera scheduling): each frame's tracks against the window's predicted motion,
// its score, the gate, and the checks the keyframes take.
#include <algorithm>
#include <utility>

#include "odometry/estimator/providers/visual_provider.h"
#include "odometry/estimator/schedule/camera_motion_check.h"

namespace uf::estimator {

// The frame's tracks seen at an earlier node of the window, each against the window's motion from that
// node to this one (schedule/camera_motion_check.h); every track is then seen here.
bool VisualProvider::CheckFrame(const PendingFrame& frame, const PoseBlockOf& pose_of) {
  const VisualScheduleConfig& schedule = config_.schedule;
  const SE3 camera_k = CameraPose(pose_of(frame.node));
  const double focal_px = sqrt_information_ * config_.pixel_sigma_px;
  std::vector<CheckedTrack> tracks;
  for (const TrackedFeature& feature : frame.features) {
    const Observation here{frame.node, {feature.normalized, feature.velocity}, frame.td0, std::nullopt};
    auto [seen, first] = last_seen_.try_emplace(feature.id, here);
    if (first) continue;
    const Observation before = std::exchange(seen->second, here);
    if (before.node >= frame.node) continue;
    const SE3 T_k_j = camera_k.inverse() * CameraPose(pose_of(before.node));
    tracks.push_back({feature.pixel, CheckTrackMotion(AtNodeTime(before), AtNodeTime(here), T_k_j, focal_px,
                                                      schedule.tolerance_px)});
  }
  if (tracks.empty()) return gate_.active();  // nothing to compare: the first frame, after a restart
  CameraScoreConfig score_config;
  score_config.reference_tracks = schedule.reference_tracks;
  score_config.min_tracks = schedule.min_tracks;
  score_config.residual_threshold_px = schedule.residual_threshold_px;
  CameraCheck check = ScoreCameraMotion(frame.node_stamp, tracks, pinhole_.width, pinhole_.height,
                                        config_.tracker.grid_cells, score_config);
  const bool was_active = gate_.active();
  if (!schedule.enabled) {
    check.active = true;
  } else if (!was_active && ToSeconds(frame.node_stamp - shut_at_) >= schedule.max_shut_s) {
    gate_.Open();  // held out long enough: the prediction it was held against has drifted meanwhile
    check.active = true;
  } else {
    check.active = gate_.Update(check.score, check.tracks_agreeing);
  }
  if (was_active && !check.active) shut_at_ = frame.node_stamp;
  checks_.push_back(check);
  return check.active;
}

std::vector<CameraCheck> VisualProvider::TakeChecks(Stamp until) {
  const auto end =
      std::find_if(checks_.begin(), checks_.end(), [until](const CameraCheck& c) { return c.stamp > until; });
  std::vector<CameraCheck> taken(checks_.begin(), end);
  checks_.erase(checks_.begin(), end);
  return taken;
}

}  // namespace uf::estimator
