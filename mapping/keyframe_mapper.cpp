#include "mapping/keyframe_mapper.h"

#include <algorithm>
#include <iterator>

#include "odometry/io/image_decode.h"

namespace uf::mapping {
namespace {

// The body pose at `stamp` between two keyframes (slerp of the rotation, lerp of the translation).
SE3 Interpolate(const Keyframe& a, const Keyframe& b, Stamp stamp) {
  const double s = static_cast<double>(stamp - a.stamp) / static_cast<double>(b.stamp - a.stamp);
  return uf::Interpolate(a.T_world_body, b.T_world_body, s);
}

}  // namespace

Expected<KeyframeMapper> KeyframeMapper::Create(const KeyframeMapperOptions& options,
                                                const DatasetDescription& description,
                                                const SE3& T_estimator_body) {
  if (Status s = ValidateColorizerOptions(options.colorizer); !s.ok()) return s;
  Expected<GlobalMap> map = GlobalMap::Create(options.map);
  if (!map) return map.status();
  KeyframeMapper mapper(options, std::move(*map));
  for (std::size_t s = 0; s < description.streams.size(); ++s) {
    const StreamInfo& stream = description.streams[s];
    if (stream.kind != SensorKind::kCamera) continue;
    if (!stream.camera_model || !stream.T_body_sensor) {
      mapper.warnings_.push_back("camera " + stream.name + " has no " +
                                 (stream.camera_model ? "extrinsic (T_body_sensor)" : "intrinsics") +
                                 ": it does not colour the map");
      continue;
    }
    mapper.cameras_.push_back(
        {static_cast<int>(s), stream.camera_model, T_estimator_body * *stream.T_body_sensor});
  }
  if (mapper.cameras_.empty())
    mapper.warnings_.push_back("no calibrated camera: the map is written without colour");
  return mapper;
}

bool KeyframeMapper::UsesCamera(int stream) const {
  for (const Camera& camera : cameras_)
    if (camera.stream == stream) return true;
  return false;
}

void KeyframeMapper::AddCameraFrame(int stream, CameraFrame frame) {
  for (const Camera& camera : cameras_) {
    if (camera.stream == stream) frames_.push_back({&camera, std::move(frame), false});
  }
}

Status KeyframeMapper::AddKeyframe(Keyframe keyframe) {
  keyframes_.push_back(std::move(keyframe));
  return MapReady(/*finishing=*/false);
}

Status KeyframeMapper::Finish() {
  const Status mapped = MapReady(/*finishing=*/true);
  keyframes_.clear();
  frames_.clear();
  next_ = 0;
  return mapped;
}

Status KeyframeMapper::MapReady(bool finishing) {
  const Stamp reach = FromSeconds(options_.max_frame_distance_s);
  for (; next_ < keyframes_.size(); ++next_) {
    if (!finishing && keyframes_.back().stamp < keyframes_[next_].stamp + reach) break;
    if (Status s = MapKeyframe(keyframes_[next_]); !s.ok()) return s;
  }
  // What a keyframe still to come needs: frames from `oldest` on, and the keyframes that bracket them.
  const Stamp oldest =
      (next_ < keyframes_.size() ? keyframes_[next_].stamp : keyframes_.back().stamp) - reach;
  while (next_ > 0 && keyframes_.size() >= 2 && keyframes_[1].stamp <= oldest) {
    keyframes_.pop_front();
    --next_;
  }
  DropFramesBefore(oldest);
  return {};
}

std::optional<SE3> KeyframeMapper::BodyPoseAt(Stamp stamp) const {
  const auto after = std::lower_bound(keyframes_.begin(), keyframes_.end(), stamp,
                                      [](const Keyframe& k, Stamp t) { return k.stamp < t; });
  if (after == keyframes_.end()) return std::nullopt;  // no extrapolation
  if (after->stamp == stamp) return after->T_world_body;
  if (after == keyframes_.begin()) return std::nullopt;
  return Interpolate(*std::prev(after), *after, stamp);
}

Status KeyframeMapper::MapKeyframe(const Keyframe& keyframe) {
  const Stamp reach = FromSeconds(options_.max_frame_distance_s);
  std::vector<CameraView> views;
  for (HeldFrame& held : frames_) {
    if (held.decode_failed || std::llabs(held.frame.stamp - keyframe.stamp) > reach) continue;
    const std::optional<SE3> T_world_body = BodyPoseAt(held.frame.stamp);
    if (!T_world_body) continue;
    if (Status s = DecodeCameraFrame(held.frame); !s.ok()) {
      held.decode_failed = true;
      warnings_.push_back("camera frame at " + std::to_string(ToSeconds(held.frame.stamp)) +
                          " s not used: " + s.message());
      continue;
    }
    CameraView view{&held.frame.image, held.camera->model.get(), *T_world_body * held.camera->T_body_cam,
                    held.frame.stamp};
    if (Status s = CheckCameraView(view); !s.ok()) {
      held.decode_failed = true;
      warnings_.push_back("camera frame at " + std::to_string(ToSeconds(held.frame.stamp)) +
                          " s not used: " + s.message());
      continue;
    }
    views.push_back(view);
  }
  std::vector<PointColor> colors;
  if (!views.empty()) {
    const Stamp stamp = keyframe.stamp;
    Expected<ColorizeResult> colored =
        Colorize(keyframe.scan_world, std::span<const Stamp>(&stamp, 1), views, options_.colorizer);
    if (!colored) return colored.status();
    colored_ += colored->colored;
    in_footprint_ += colored->in_footprint;
    colors.assign(colored->colors.begin(), colored->colors.end());
  }
  return map_.Insert(keyframe, colors);
}

void KeyframeMapper::DropFramesBefore(Stamp stamp) {
  while (!frames_.empty() && frames_.front().frame.stamp < stamp) frames_.pop_front();
}

}  // namespace uf::mapping
