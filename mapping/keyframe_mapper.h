// Keyframes into the global map (OpenVDB), coloured from the camera images taken around them: the map
// stage of `ultrafusion run` (docs/ARCHITECTURE.md) feeds it the estimator's keyframes, or with --from map
// the scans deskewed with an earlier trajectory (deskew_with_trajectory.h).
//
// A keyframe carries its pose at the middle of its sweep; a camera frame is taken at its own time, so the
// camera pose is interpolated between the keyframes that bracket the frame (slerp/lerp of T_world_body),
// then T_world_cam = T_world_body(t_frame) * T_body_cam. A keyframe is therefore coloured once the next one
// has arrived (or at Finish, from frames up to its own time). Frames farther than max_frame_distance_s from
// the keyframe are not used, and a frame is decoded only when a keyframe uses it.
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
  double max_frame_distance_s = 0.1;  // camera frames used for a keyframe: within this of its stamp
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
  // Colours and inserts `keyframe`, interpolating camera poses between `before` and `after` (either may be
  // missing: frames outside the bracket are not used).
  Status MapKeyframe(const Keyframe& keyframe, const Keyframe* before, const Keyframe* after);
  std::optional<SE3> BodyPoseAt(Stamp stamp, const Keyframe& keyframe, const Keyframe* before,
                                const Keyframe* after) const;
  void DropFramesBefore(Stamp stamp);

  KeyframeMapperOptions options_;
  GlobalMap map_;
  std::vector<Camera> cameras_;
  std::deque<HeldFrame> frames_;
  std::deque<Keyframe> keyframes_;  // at most two: the one waiting for its successor, and its predecessor
  std::vector<std::string> warnings_;
  std::size_t colored_ = 0, in_footprint_ = 0;
};

}  // namespace uf::mapping
