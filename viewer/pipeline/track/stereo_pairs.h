// `ultrafusion track --stereo`: pairs the tracked camera's frames with the second camera's by stamp (within
// kStereoPairTolerance) and matches each pair (odometry/estimator/visual/stereo_matcher.h). Frames arrive in
// stamp order, left or right first; a frame without a partner is dropped once a later one of its camera
// comes.
#pragma once

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "odometry/estimator/visual/stereo_matcher.h"

namespace uf::pipeline {

inline constexpr Stamp kStereoPairTolerance = 1'000'000;  // 1 ms

// One matched pair: the index of the left frame in the job's frames, and its stereo statistics.
using StereoPairResult = std::pair<std::size_t, estimator::StereoStats>;

class StereoPairs {
 public:
  // Keeps references to both camera models: they must outlive this.
  StereoPairs(const CameraModel& left, const CameraModel& right, const SE3& T_left_right);

  // A left frame, tracked (its features) and `index` in the job's frames; the pair's result when the right
  // frame of its stamp is already here. Errors: MatchStereo's (images of the wrong size).
  Expected<std::optional<StereoPairResult>> AddLeft(std::size_t index, Stamp stamp, Image image,
                                                    std::vector<estimator::TrackedFeature> features);
  // A right frame, decoded; the pair's result when the left frame of its stamp is already here.
  Expected<std::optional<StereoPairResult>> AddRight(Stamp stamp, Image image);

 private:
  Expected<std::optional<StereoPairResult>> TryMatch();

  const CameraModel& left_camera_;
  const CameraModel& right_camera_;
  SE3 T_left_right_;
  struct Left {
    std::size_t index = 0;
    Stamp stamp = 0;
    Image image;
    std::vector<estimator::TrackedFeature> features;
  };
  std::optional<Left> left_;
  std::optional<std::pair<Stamp, Image>> right_;
};

}  // namespace uf::pipeline
