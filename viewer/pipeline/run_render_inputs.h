// What `ultrafusion render RUN_DIR --stamps FILE [--camera NAME]` renders from a run folder: the run's splats
// (splats.ply), one of its cameras (cameras.yaml, run/run_cameras.h) and that camera's poses at the stamps
// of FILE (one time in seconds per line, ReadStampsFile), placed on trajectory.tum with run.json's frames
// (run/run_camera_poses.h: T_M_C(t) = T_M_W * T_W_F(t) * T_F_B * T_B_C), in the frame of the splats.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "odometry/types/camera_model.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::pipeline {

struct RenderInputs {
  std::filesystem::path splats;               // a splat file: .ply or .glb
  std::string camera_name;                    // the camera stream ("" for a camera file)
  std::shared_ptr<const CameraModel> camera;  // intrinsics and distortion, native size
  std::vector<Stamp> stamps;                  // one view each, in the order given
  std::vector<SE3> T_world_camera;            // per stamp, in the splats' frame
};

// Errors name the file: no run.json, no splats.ply (the run trained none), no cameras.yaml, an unknown
// camera (the error lists the run's cameras), a bad stamps file (file:line and the text), a stamp outside
// trajectory.tum's span.
Expected<RenderInputs> ReadRunRenderInputs(const std::filesystem::path& folder,
                                           const std::string& stamps_file, const std::string& camera);

}  // namespace uf::pipeline
