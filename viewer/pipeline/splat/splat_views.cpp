#include "viewer/pipeline/splat/splat_views.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "odometry/io/for_each_measurement.h"
#include "odometry/io/image_decode.h"

namespace uf::pipeline {
namespace {

using app::DefaultSize;

// The view of one decoded image: undistorted to the model's pinhole when it has distortion, resized to the
// training size, quantised to 8 bits (the source's precision) for storage.
StoredView MakeView(const Image& image, const CameraModel& model, const PinholeIntrinsics& native,
                    const PinholeIntrinsics& target, const SE3& T_world_camera, Stamp stamp,
                    std::span<const Eigen::Vector3f> depth_points) {
  std::vector<float> rgb = splat::ToRgbFloat(image);
  if (IsDistorted(model)) rgb = splat::Undistort(rgb, model, native);
  if (target.width != native.width || target.height != native.height)
    rgb = splat::ResizeArea(rgb, native.width, native.height, 3, target.width, target.height);
  StoredView view;
  view.stamp = stamp;
  view.camera.pinhole = target;
  view.camera.T_world_camera = T_world_camera;
  view.rgb.resize(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i)
    view.rgb[i] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(rgb[i], 0.0f, 1.0f)));
  if (!depth_points.empty()) view.depth = splat::ProjectDepth(depth_points, view.camera);
  return view;
}

// The camera's mask at the training size (see the header); null when every pixel counts.
Expected<std::shared_ptr<const std::vector<std::uint8_t>>> CameraMask(const CameraModel& model,
                                                                      const PinholeIntrinsics& native,
                                                                      const PinholeIntrinsics& target,
                                                                      const std::string& mask_image) {
  const std::size_t pixels = static_cast<std::size_t>(native.width) * native.height;
  std::vector<std::uint8_t> mask(pixels, 1);
  if (IsDistorted(model)) mask = splat::UndistortedCoverage(model, native);
  if (!mask_image.empty()) {
    Expected<Image> masked = ReadMaskFile(mask_image, native.width, native.height);
    if (!masked) return Status::Error("splat.mask_image: " + masked.error());
    for (std::size_t p = 0; p < pixels; ++p)
      if (masked->pixels[p] == 0) mask[p] = 0;
  }
  if (std::all_of(mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; }))
    return std::shared_ptr<const std::vector<std::uint8_t>>();
  if (target.width != native.width || target.height != native.height)
    mask = splat::ResizeMask(mask, native.width, native.height, target.width, target.height);
  return std::make_shared<const std::vector<std::uint8_t>>(std::move(mask));
}

}  // namespace

Expected<SplatCameraStream> FindSplatCamera(const DatasetDescription& description, const SE3& T_output_body) {
  for (std::size_t s = 0; s < description.streams.size(); ++s) {
    const StreamInfo& stream = description.streams[s];
    if (stream.kind != SensorKind::kCamera) continue;
    const std::string where = description.path.string() + ": camera " + stream.name;
    if (!stream.camera_model)
      return Status::Error(where + " has no intrinsics (camera model): its images cannot be placed");
    if (!stream.T_body_sensor)
      return Status::Error(where + " has no extrinsic (T_body_sensor): its images cannot be placed");
    if (!PinholeOf(*stream.camera_model))
      return Status::Error(where + ": unsupported camera model (pinhole-radtan and equidistant are)");
    return SplatCameraStream{static_cast<int>(s), stream.name, stream.camera_model,
                             T_output_body * *stream.T_body_sensor};
  }
  return Status::Error(description.path.string() +
                       ": no camera stream, so there are no images to train splats on (nothing trained)");
}

bool KeyframeSelector::Select(const SE3& T_world_camera) {
  if (last_) {
    const SE3 motion = last_->inverse() * T_world_camera;
    const double angle_deg = motion.so3().angle() * 180.0 / std::numbers::pi;
    if (motion.translation().norm() < distance_m_ && angle_deg < angle_deg_) return false;
  }
  last_ = T_world_camera;
  return true;
}

splat::TrainingView ToTrainingView(const StoredView& view) {
  splat::TrainingView training;
  training.camera = view.camera;
  training.rgb.resize(view.rgb.size());
  for (std::size_t i = 0; i < view.rgb.size(); ++i) training.rgb[i] = view.rgb[i] / 255.0f;
  training.depth = view.depth;
  if (view.mask) training.mask = *view.mask;
  return training;
}

void SplitHeldOut(std::vector<StoredView> selected, int stride, std::vector<StoredView>& train,
                  std::vector<StoredView>& test) {
  const std::size_t n = selected.size();
  const bool middle_only = n >= 3 && n < static_cast<std::size_t>(stride / 2 + 2);  // the rule holds none out
  for (std::size_t i = 0; i < n; ++i) {
    const bool held_out = middle_only ? i == n / 2 : static_cast<int>(i % stride) == stride / 2 && i + 1 < n;
    (held_out ? test : train).push_back(std::move(selected[i]));
  }
}

Expected<SplatViews> LoadSplatViews(MeasurementStream& stream, const SplatCameraStream& camera,
                                    const ViewLoading& loading,
                                    const std::function<void(std::int64_t)>& progress) {
  const SplatConfig& config = *loading.config;
  SplatViews views;
  views.camera_name = camera.name;
  views.model = camera.model;
  const PinholeIntrinsics native = *PinholeOf(*camera.model);
  int width = config.width, height = config.height;
  if (width == 0) DefaultSize(native.width, native.height, config.max_width, width, height);
  views.pinhole = splat::ScalePinhole(native, width, height);
  Expected<std::shared_ptr<const std::vector<std::uint8_t>>> mask =
      CameraMask(*camera.model, native, views.pinhole, config.mask_image);
  if (!mask) return mask.status();
  if (*mask) views.masked_pixels = static_cast<std::size_t>(std::count((*mask)->begin(), (*mask)->end(), 0));
  KeyframeSelector selector(config.keyframe_distance_m, config.keyframe_angle_deg);
  std::vector<StoredView> selected;
  const Status read = ForEachMeasurement(stream, [&](Measurement& m) {
    auto* frame = std::get_if<CameraFrame>(&m.data);
    if (!frame || m.stream != camera.stream) return Status();
    ++views.images;
    if (progress) progress(views.images);
    const std::optional<SE3> T_world_frame = loading.trajectory->PoseAt(frame->stamp);
    if (!T_world_frame) {
      ++views.outside_trajectory;
      return Status();
    }
    // T_M_C = T_M_W * T_W_F(t) * T_F_C (see the header).
    const SE3 T_map_camera = loading.T_map_world * *T_world_frame * camera.T_frame_camera;
    if (!selector.Select(T_map_camera)) return Status();
    if (!DecodeCameraFrame(*frame).ok() || frame->image.width != native.width ||
        frame->image.height != native.height) {
      ++views.undecodable;
      return Status();
    }
    StoredView view = MakeView(frame->image, *camera.model, native, views.pinhole, T_map_camera, frame->stamp,
                               loading.depth_points);
    view.mask = *mask;
    selected.push_back(std::move(view));
    return Status();
  });
  if (!read.ok()) return read;
  SplitHeldOut(std::move(selected), config.holdout_stride, views.train, views.test);
  return views;
}

}  // namespace uf::pipeline
