// What the windows' starts read from the camera's waiting frames (visual_provider.h): whether the camera is
// still, and the tracks over the frames of a visual-inertial start (init/visual_inertial_poses.h), with the
// stereo rig's depths.
#include "odometry/estimator/providers/visual_provider.h"
#include "odometry/types/printf_text.h"

namespace uf::estimator {

std::optional<std::string> VisualProvider::NotStillReason(const std::vector<Stamp>& node_stamps) const {
  for (Stamp stamp : node_stamps) {
    const auto frame = waiting_.find(stamp);
    if (frame == waiting_.end()) continue;
    double sum = 0;
    int tracked = 0;
    for (const TrackedFeature& f : frame->second.features)
      if (f.length > 1) {
        sum += (f.pixel - f.previous_pixel).norm();
        ++tracked;
      }
    if (tracked > 0 && sum / tracked > config_.max_static_flow_px)
      return PrintfText("the camera moves (features %.2f px per frame at ", sum / tracked) +
             StampText(frame->second.camera_stamp) +
             PrintfText(", above visual.max_static_flow_px %.2f)", config_.max_static_flow_px);
  }
  return std::nullopt;
}

std::vector<FeatureTrack> VisualProvider::Tracks(const std::vector<Stamp>& node_stamps) const {
  std::map<long, FeatureTrack> tracks;
  for (std::size_t k = 0; k < node_stamps.size(); ++k) {
    const auto frame = waiting_.find(node_stamps[k]);
    if (frame == waiting_.end()) continue;
    for (const TrackedFeature& f : frame->second.features) {
      FeatureTrack& track = tracks[f.id];
      track.observations.emplace_back(k, f.normalized);
      if (const auto right = frame->second.right.find(f.id); right != frame->second.right.end())
        track.depths.emplace_back(k, right->second.depth_m);  // a stereo rig's (SetStereo)
    }
  }
  std::vector<FeatureTrack> out;
  for (auto& [id, track] : tracks) out.push_back(std::move(track));
  return out;
}

}  // namespace uf::estimator
