// Keyframes into the global map (OpenVDB), coloured from the camera images taken around them: the map
// stage of `ultrafusion run` (docs/ARCHITECTURE.md) feeds it the estimator's keyframes, or with --from map
// the scans deskewed with an earlier trajectory (deskew_with_trajectory.h).
//
// A keyframe carries its pose at the middle of its sweep; a camera frame is taken at its own time, so the
// camera pose is interpolated between the keyframes that bracket the frame (slerp/lerp of T_world_body),
// then T_world_cam = T_world_body(t_frame) * T_body_cam. A keyframe is coloured from every frame within
// max_frame_distance_s of it, so it waits until a keyframe that far after it has arrived (or Finish, which
// uses the frames up to the last keyframe: no extrapolation); the mapper holds the keyframes and frames of
// that window. Each point takes the colour of the nearest image in time in which it is visible (colorizer.h):
// the other images of the window colour what the nearest one does not see (behind a pole, a parked car).
// A frame is decoded only when a keyframe uses it.
//
// Cameras without intrinsics or without an extrinsic (T_body_sensor) cannot colour: the map is then built
// uncoloured and a warning says why. Frames that fail to decode are skipped with a warning.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "mapping/colorizer.h"
#include "mapping/global_map.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/keyframe.h"

namespace uf::mapping {

struct KeyframeMapperOptions {
  GlobalMapConfig map;
  ColorizerOptions colorizer;
  // Camera frames used for a keyframe: within this of its stamp. On KITTI raw (images at 5 Hz, scans at
  // 10 Hz) 0.1 s gives a scan 1-2 images and colours 93.5 % of the in-image points, 0.3 s 3-4 images.
  double max_frame_distance_s = 0.3;
};

class KeyframeMapper {
 public:
  // T_estimator_body: the dataset's body frame in the estimator's body frame (LO: T_lidar_body, LIO:
  // T_imu_body), to place the cameras. Fails for an invalid map or colorizer config.
  static Expected<KeyframeMapper> Create(const KeyframeMapperOptions& options,
                                         const DatasetDescription& description, const SE3& T_estimator_body);

  // Whether `stream` is a camera this mapper colours with.
  bool UsesCamera(int stream) const;
  void AddCameraFrame(int stream, CameraFrame frame);
  Status AddKeyframe(Keyframe keyframe);
  // Colours and inserts the keyframes still held.
  Status Finish();

  const GlobalMap& map() const { return map_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  std::size_t colored_points() const { return colored_; }
  std::size_t in_footprint_points() const { return in_footprint_; }

 private:
  struct Camera {
    int stream = -1;
    std::shared_ptr<const CameraModel> model;
    SE3 T_body_cam;  // estimator body <- camera
  };
  struct HeldFrame {
    const Camera* camera = nullptr;
    CameraFrame frame;
    bool decode_failed = false;
  };
  KeyframeMapper(KeyframeMapperOptions options, GlobalMap map) : options_(options), map_(std::move(map)) {}
  // Maps the held keyframes that have a keyframe max_frame_distance_s after them (every one when
  // finishing), then drops the keyframes and frames that no keyframe still to map needs.
  Status MapReady(bool finishing);
  // Colours and inserts `keyframe` from the held frames within max_frame_distance_s of it.
  Status MapKeyframe(const Keyframe& keyframe);
  // The body pose at `stamp`, interpolated between the held keyframes that bracket it; none outside them.
  std::optional<SE3> BodyPoseAt(Stamp stamp) const;
  void DropFramesBefore(Stamp stamp);

  KeyframeMapperOptions options_;
  GlobalMap map_;
  std::vector<Camera> cameras_;
  std::deque<HeldFrame> frames_;
  std::deque<Keyframe> keyframes_;  // in time order: those waiting to be mapped and those before them that
  std::size_t next_ = 0;            // ... bracket their frames; next_: the first not mapped yet
  std::vector<std::string> warnings_;
  std::size_t colored_ = 0, in_footprint_ = 0;
};

}  // namespace uf::mapping
