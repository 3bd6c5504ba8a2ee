// A camera of a run at any time, in the frame of the run's map and splats (frames of run_frames.h):
//
//   T_M_C(t) = T_M_W * T_W_F(t) * T_F_B * T_B_C
//
// T_W_F(t): trajectory.tum, the stored pose at one of its stamps, else interpolated between the bracketing
// poses (Trajectory::PoseAt: slerp of the rotation, lerp of the translation; no extrapolation); T_M_W and
// T_F_B from run.json; T_B_C the camera's T_body_sensor (cameras.yaml, run_cameras.h). The splat training
// places its images the same way (splat_views.h), so a stamp of a training image gives that image's pose.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::pipeline {

struct CameraPlacement {
  SE3 T_map_world;     // T_M_W
  SE3 T_frame_camera;  // T_F_C = T_F_B * T_B_C
};

// T_M_C at each stamp, in the order given (repeats and any order allowed). A stamp outside the trajectory's
// span [first, last stamp] is an error naming the stamp, `stamps_file` and the span of `trajectory_file`.
Expected<std::vector<SE3>> CameraPosesAt(const Trajectory& trajectory, const CameraPlacement& placement,
                                         std::span<const Stamp> stamps, const std::string& trajectory_file,
                                         const std::string& stamps_file);

}  // namespace uf::pipeline
