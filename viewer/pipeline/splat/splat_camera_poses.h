// Where a run's camera was when it took an image, in the frame of the run's map.
//
// Frames (T_a_b maps b to a). trajectory.tum holds T_W_F(t): the pose of the run's output frame F (the
// LiDAR or the IMU, run.json output_frame) in the trajectory's world W. The dataset gives each sensor's
// T_body_sensor relative to its body frame B; the camera's pose in F is
//   T_F_C = T_F_B * T_B_C,   T_F_B = T_B_lidar^-1 (F = lidar) or T_B_imu^-1 (F = imu; identity when the IMU
//                            stream has no T_body_sensor: the body is the IMU, as ImuFromLidar takes it).
// The map (map.vdb) is in the estimator's world M, which is W except for an LO run written in the IMU frame
// (ToImuFrame moves the world to the first IMU pose): T_M_W = T_imu_lidar^-1 there. So
//   T_M_C(t) = T_M_W * T_W_F(t) * T_F_C,
// with T_W_F(t) interpolated between the bracketing poses (slerp of the rotation, lerp of the translation,
// Trajectory::PoseAt); no extrapolation outside the trajectory's span.
#pragma once

#include <optional>
#include <string>

#include "odometry/io/dataset_reader.h"
#include "odometry/types/trajectory.h"

namespace uf::app {

// T_F_B for output_frame "lidar" or "imu"; an error names a missing LiDAR stream or its missing
// T_body_sensor (needed to place the LiDAR frame relative to the camera).
Expected<SE3> OutputFrameFromBody(const DatasetDescription& description, const std::string& output_frame);

// T_M_W: T_imu_lidar^-1 for an LO run (mode "lo") written in the IMU frame by the odometry stage, else the
// identity. from_trajectory: the map was remade from trajectory.tum (`run --from map`), which keeps W.
Expected<SE3> MapFromTrajectoryWorld(const DatasetDescription& description, const std::string& mode,
                                     const std::string& output_frame, bool from_trajectory);

}  // namespace uf::app
