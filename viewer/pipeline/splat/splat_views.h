// The training and held-out views of a run: the dataset's first camera stream read again, each image placed
// at its stamp on the run's trajectory, keyframe images selected by camera motion, made into pinhole images
// at the training resolution (splat/views/training_images.h), and split (SplitHeldOut): every
// holdout_stride-th selected image is held out for testing and never trained on. One mask for all of them:
// the pixels an undistorted view cannot fill and the black pixels of SplatConfig::mask_image.
//
// Where the camera was (frames of run_frames.h, recorded in run.json): trajectory.tum holds T_W_F(t), the
// camera sits at T_F_C = T_F_B * T_B_C in the trajectory's frame (T_B_C its T_body_sensor), and the map is
// in M, so
//   T_M_C(t) = T_M_W * T_W_F(t) * T_F_C,
// with T_W_F(t) interpolated between the bracketing poses (Trajectory::PoseAt: slerp and lerp); images
// outside the trajectory's span are not used (no extrapolation).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "odometry/io/measurement_stream.h"
#include "odometry/types/trajectory.h"
#include "splat/training/training_options.h"
#include "splat/views/training_images.h"
#include "viewer/app/config/splat_config.h"

namespace uf::pipeline {

using app::SplatConfig;

// The camera images come from: the dataset's first camera stream, its model and T_F_C (its pose in the
// trajectory's frame F).
struct SplatCameraStream {
  int stream = -1;
  std::string name;
  std::shared_ptr<const CameraModel> model;
  SE3 T_frame_camera;
};

// Errors: no camera stream ("train nothing": the message says so), a camera without intrinsics or without
// T_body_sensor, a camera model that is not PinholeRadtan or Equidistant. T_output_body: T_F_B.
Expected<SplatCameraStream> FindSplatCamera(const DatasetDescription& description, const SE3& T_output_body);

// Selects an image when the camera moved >= distance_m or turned >= angle_deg since the last selected one
// (the first image is always selected).
class KeyframeSelector {
 public:
  KeyframeSelector(double distance_m, double angle_deg) : distance_m_(distance_m), angle_deg_(angle_deg) {}
  bool Select(const SE3& T_world_camera);

 private:
  double distance_m_, angle_deg_;
  std::optional<SE3> last_;
};

// A view kept compact between loading and training: 8-bit rgb at the training resolution.
struct StoredView {
  Stamp stamp = 0;
  splat::SplatCamera camera;      // training resolution, T_world_camera in the map frame
  std::vector<std::uint8_t> rgb;  // width x height x 3
  std::vector<float> depth;       // LiDAR depth per pixel (0: none); empty without depth
  // 0 where the pixel is not trained on nor scored (TrainingView::mask), shared by the camera's views;
  // null: every pixel counts.
  std::shared_ptr<const std::vector<std::uint8_t>> mask;
};

splat::TrainingView ToTrainingView(const StoredView& view);

struct SplatViews {
  std::vector<StoredView> train, test;
  PinholeIntrinsics pinhole;                 // the training images' camera
  std::string camera_name;                   // the stream
  std::shared_ptr<const CameraModel> model;  // the camera's own model (native size, distortion)
  std::int64_t images = 0;                   // frames of the camera stream
  std::int64_t outside_trajectory = 0;       // dropped: no pose at their stamp
  std::int64_t undecodable = 0;              // dropped: could not be decoded
  std::size_t masked_pixels = 0;             // of the training resolution (StoredView::mask)
};

struct ViewLoading {
  const Trajectory* trajectory = nullptr;  // T_W_F
  SE3 T_map_world;                         // T_M_W
  const SplatConfig* config = nullptr;
  std::span<const Eigen::Vector3f> depth_points;  // map points for LiDAR depth; empty: no depth
};

// The held-out split of the selected views (in time order): index % stride == stride / 2, and never the last
// one; when that holds none out, the middle one of 3 or more. Each held-out view then has training views
// before and after it along the trajectory, so the score is that of a novel view between the training views.
// 3DGS holds out index % stride == 0, which on a trajectory makes the first image an extrapolation: its edges
// show what no training image saw (KITTI drive 0009: 12.6 dB against 17-18 dB for the views between).
void SplitHeldOut(std::vector<StoredView> selected, int stride, std::vector<StoredView>& train,
                  std::vector<StoredView>& test);

// Reads the stream to its end and keeps the selected views; `progress` is called with the images read.
// Errors: a mask_image that cannot be read or decoded, or not of the camera's size (naming the file).
Expected<SplatViews> LoadSplatViews(MeasurementStream& stream, const SplatCameraStream& camera,
                                    const ViewLoading& loading,
                                    const std::function<void(std::int64_t)>& progress = {});

}  // namespace uf::pipeline
