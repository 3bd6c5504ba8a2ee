// The stereo rig of the camera's part of the window (visual_provider.h; docs/METHOD.md "Stereo in the
// window"): the rig, the pairing of its frames, and the pair's depth for a new landmark.
#include "odometry/estimator/providers/visual_provider.h"
#include "odometry/types/stamp.h"

namespace uf::estimator {
namespace {

// A stereo rig's frames are a pair when their stamps are this close.
constexpr Stamp kStereoPairTolerance = 1'000'000;  // 1 ms

}  // namespace

Status VisualProvider::SetStereo(StereoRig rig) {
  if (!rig.left || !rig.right) return Status::Error("visual.stereo: no camera model");
  const std::optional<PinholeIntrinsics> right = PinholeOf(*rig.right);
  if (!right) return Status::Error("visual.stereo: the right camera has no pinhole intrinsics");
  const SE3& T = rig.T_left_right;
  if (!T.translation().allFinite() || !T.so3().matrix().allFinite() || !(T.translation().norm() > 1e-3))
    return Status::Error("visual.stereo: the right camera's extrinsic has no baseline (or is not finite)");
  Stereo stereo;
  stereo.T_right_left = T.inverse();
  stereo.sqrt_information = 0.5 * (right->fx + right->fy) / config_.pixel_sigma_px;
  stereo.rig = std::move(rig);
  stereo_ = std::move(stereo);
  return {};
}

Status VisualProvider::SetStereoIf(const std::shared_ptr<const CameraModel>& left, const SE3& T_body_left,
                                   const std::shared_ptr<const CameraModel>& right, const SE3& T_body_right,
                                   const std::string& section) {
  if (!config_.stereo || !right) return {};
  if (Status s = SetStereo({left, right, T_body_left.inverse() * T_body_right}); !s.ok())
    return Status::Error(section + "." + s.message());
  return {};
}

void VisualProvider::AddRightFrame(Stamp stamp, const Image& image, std::vector<std::string>& warnings) {
  if (!stereo_) return;
  stereo_->right.emplace(stamp, image);
  MatchHeldPair();
  TakeStereoWarnings(warnings);
}

void VisualProvider::TakeStereoWarnings(std::vector<std::string>& warnings) {
  warnings.insert(warnings.end(), stereo_warnings_.begin(), stereo_warnings_.end());
  stereo_warnings_.clear();
}

void VisualProvider::ReleaseLeftAlone() {
  if (!stereo_->left) return;
  Wait(stereo_->left->first, std::move(stereo_->left_features), {});
  stereo_->left.reset();
}

void VisualProvider::MatchHeldPair() {
  Stereo& s = *stereo_;
  if (!s.left || !s.right) return;
  const Stamp stamp = s.left->first;
  if (s.right->first < stamp - kStereoPairTolerance) {  // a right frame whose left frame never came
    s.right.reset();
    return;
  }
  if (s.right->first > stamp + kStereoPairTolerance) return;  // the left frame goes on alone with the next
  Expected<StereoResult> matched = MatchStereo(s.left_features, s.left->second, s.right->second, *s.rig.left,
                                               *s.rig.right, s.rig.T_left_right);
  if (!matched)
    stereo_warnings_.push_back("stereo pair at " + StampText(stamp) + ": " + matched.error() +
                               "; the left frame is used alone");
  else
    ++stereo_pairs_;
  Wait(stamp, std::move(s.left_features), matched ? matched->matches : std::vector<StereoMatch>());
  s.left.reset();
  s.right.reset();
}

std::optional<double> VisualProvider::StereoInverseDepth(const Landmark& landmark,
                                                         const std::vector<SE3>& cameras) const {
  const Observation& anchor = landmark.observations.front();
  if (!stereo_ || !anchor.right) return std::nullopt;
  return CheckedInverseDepth(landmark, cameras, anchor.right->depth_m);
}

}  // namespace uf::estimator
