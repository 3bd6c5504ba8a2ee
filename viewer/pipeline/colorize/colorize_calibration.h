// Camera intrinsics and the LiDAR->camera extrinsic for `ultrafusion colorize`, read from either
//   - the JSON files of ../shared/data/lidar-camera-pair (one top-level entry "<name>-intrinsic" with
//     param.img_dist_w/h, param.cam_K.data (3x3) and param.cam_dist.data ([[k1, k2, p1, p2(, k3)]]),
//     radial-tangential; one entry "<lidar>-to-<camera>-extrinsic" with param.sensor_calib.data, the 4x4
//     T_cam_lidar that maps LiDAR points into the camera frame), or
//   - the project's YAML: a calibration file (odometry/io/calibration_file.h) or a dataset folder's
//     dataset.yaml (odometry/io/folders/ultrafusion_dataset_writer.h). The first camera is used; the
//     extrinsic is T_cam_lidar = T_body_cam^-1 * T_body_lidar from the first lidar's and first camera's
//     T_body_sensor.
// Errors name the file, the key and the value.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "odometry/types/camera_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::pipeline {

struct LoadedIntrinsics {
  std::shared_ptr<const CameraModel> camera;  // of the calibrated image size
  std::string description;                    // e.g. "center_camera-intrinsic of camera_intrinsic.json"
};

struct LoadedExtrinsic {
  SE3 T_cam_lidar;          // p_cam = T_cam_lidar * p_lidar
  std::string description;  // where it came from
};

// By extension: .json, or .yaml / .yml.
Expected<LoadedIntrinsics> LoadIntrinsics(const std::string& path);
Expected<LoadedExtrinsic> LoadExtrinsic(const std::string& path);

// Whether the extension is one LoadIntrinsics / LoadExtrinsic reads.
bool IsCalibrationExtension(const std::string& path);

// The camera model for an image of width x height taken by a camera calibrated at another size: the image
// is taken as a centred crop (or a centred border, when larger) of the calibrated image, so pixel
// coordinates shift by half the size difference and the principal point moves by
//   (cx, cy) -> (cx + (width - w_cal) / 2, cy + (height - h_cal) / 2).
// Focal lengths and distortion are unchanged. `shift` receives the principal point shift in pixels.
// Errors: a camera model this does not know, or a principal point leaving the image.
Expected<std::shared_ptr<const CameraModel>> FitCameraToImage(const CameraModel& camera, int width,
                                                              int height, Eigen::Vector2d* shift = nullptr);

}  // namespace uf::pipeline
