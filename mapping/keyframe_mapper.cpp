#include "mapping/keyframe_mapper.h"

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
  if (!keyframes_.empty()) {
    const Keyframe* before = keyframes_.size() >= 2 ? &keyframes_[keyframes_.size() - 2] : nullptr;
    if (Status s = MapKeyframe(keyframes_.back(), before, &keyframe); !s.ok()) return s;
  }
  keyframes_.push_back(std::move(keyframe));
  while (keyframes_.size() > 2) keyframes_.pop_front();
  DropFramesBefore(keyframes_.front().stamp - FromSeconds(options_.max_frame_distance_s));
  return {};
}

Status KeyframeMapper::Finish() {
  if (!keyframes_.empty()) {
    const Keyframe* before = keyframes_.size() >= 2 ? &keyframes_[keyframes_.size() - 2] : nullptr;
    if (Status s = MapKeyframe(keyframes_.back(), before, nullptr); !s.ok()) return s;
  }
  keyframes_.clear();
  frames_.clear();
  return {};
}

std::optional<SE3> KeyframeMapper::BodyPoseAt(Stamp stamp, const Keyframe& keyframe, const Keyframe* before,
                                              const Keyframe* after) const {
  if (stamp == keyframe.stamp) return keyframe.T_world_body;
  if (before && stamp >= before->stamp && stamp < keyframe.stamp)
    return Interpolate(*before, keyframe, stamp);
  if (after && stamp > keyframe.stamp && stamp <= after->stamp) return Interpolate(keyframe, *after, stamp);
  return std::nullopt;  // no extrapolation
}

Status KeyframeMapper::MapKeyframe(const Keyframe& keyframe, const Keyframe* before, const Keyframe* after) {
  const Stamp reach = FromSeconds(options_.max_frame_distance_s);
  std::vector<CameraView> views;
  for (HeldFrame& held : frames_) {
    if (held.decode_failed || std::llabs(held.frame.stamp - keyframe.stamp) > reach) continue;
    const std::optional<SE3> T_world_body = BodyPoseAt(held.frame.stamp, keyframe, before, after);
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
