// The calibration of a KITTI raw drive, from its date folder's calib_imu_to_velo.txt, calib_velo_to_cam.txt
// and calib_cam_to_cam.txt, as the project's extrinsics (body = the OXTS IMU frame) and camera models.
// Internal to uf_io.
//
// KITTI's conventions (devkit readme):
//   calib_imu_to_velo  R, T:  X_velo = R X_imu + T
//   calib_velo_to_cam  R, T:  X_cam0 = R X_velo + T                (cam0: the unrectified left grey camera)
//   calib_cam_to_cam   R_0i, T_0i: X_cami = R_0i X_cam0 + T_0i     (unrectified camera i; K_0i, D_0i, S_0i)
//                      R_rect_00: X_rect0 = R_rect_00 X_cam0        (the common rectified frame)
//                      P_rect_0i = K [I | t_i] (3x4): projects X_rect0 into the rectified image i, so the
//                      rectified camera i sits at X_recti = X_rect0 + t_i with t_i = K^-1 P_rect_0i(:, 3)
// Rectified images (the "sync" package) are pinhole without distortion, S_rect_0i in size; unrectified ones
// (the "extract" package) use K_0i, D_0i (k1 k2 p1 p2 k3, OpenCV's plumb bob) and S_0i.
#pragma once

#include <filesystem>
#include <memory>

#include "odometry/types/camera_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf {

struct KittiRawCamera {
  std::shared_ptr<const CameraModel> model;
  SE3 T_imu_camera;  // p_imu = T_imu_camera * p_camera
};

struct KittiRawRig {
  SE3 T_imu_velo;  // p_imu = T_imu_velo * p_velo
  SE3 T_velo_cam0;
};

// Reads calib_imu_to_velo.txt and calib_velo_to_cam.txt in `date_folder`. Errors name the file (a missing
// one: where it was looked for).
Expected<KittiRawRig> ReadKittiRawRig(const std::filesystem::path& date_folder);

// Camera `index` (0..3) from calib_cam_to_cam.txt: the rectified camera when `rectified`, else the raw one.
Expected<KittiRawCamera> ReadKittiRawCamera(const std::filesystem::path& date_folder, const KittiRawRig& rig,
                                            int index, bool rectified);

}  // namespace uf
