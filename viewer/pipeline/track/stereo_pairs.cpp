#include "viewer/pipeline/track/stereo_pairs.h"

#include <cstdlib>

namespace uf::pipeline {

StereoPairs::StereoPairs(const CameraModel& left, const CameraModel& right, const SE3& T_left_right)
    : left_camera_(left), right_camera_(right), T_left_right_(T_left_right) {}

Expected<std::optional<StereoPairResult>> StereoPairs::AddLeft(
    std::size_t index, Stamp stamp, Image image, std::vector<estimator::TrackedFeature> features) {
  left_ = Left{index, stamp, std::move(image), std::move(features)};
  return TryMatch();
}

Expected<std::optional<StereoPairResult>> StereoPairs::AddRight(Stamp stamp, Image image) {
  right_.emplace(stamp, std::move(image));
  return TryMatch();
}

Expected<std::optional<StereoPairResult>> StereoPairs::TryMatch() {
  if (!left_ || !right_ || std::llabs(left_->stamp - right_->first) > kStereoPairTolerance)
    return std::optional<StereoPairResult>();
  Expected<estimator::StereoResult> matched = estimator::MatchStereo(
      left_->features, left_->image, right_->second, left_camera_, right_camera_, T_left_right_);
  const std::size_t index = left_->index;
  left_.reset();
  right_.reset();
  if (!matched) return matched.status();
  return std::optional<StereoPairResult>(StereoPairResult{index, matched->stats});
}

}  // namespace uf::pipeline
