#include "viewer/pipeline/run/run_camera_poses.h"

namespace uf::pipeline {

Expected<std::vector<SE3>> CameraPosesAt(const Trajectory& trajectory, const CameraPlacement& placement,
                                         std::span<const Stamp> stamps, const std::string& trajectory_file,
                                         const std::string& stamps_file) {
  std::vector<SE3> poses;
  poses.reserve(stamps.size());
  for (Stamp t : stamps) {
    const std::optional<SE3> T_world_frame = trajectory.PoseAt(t);
    if (!T_world_frame) {
      // "[first, last] s" (built in steps: GCC 12 warns wrongly on "[" + std::string temporaries).
      std::string span = "no stamps";
      if (trajectory.has_stamps()) {
        span = FormatSeconds(trajectory.stamps.front()) + ", " + FormatSeconds(trajectory.stamps.back());
        span.insert(0, 1, '[');
        span += "] s";
      }
      return Status::Error(stamps_file + ": stamp " + FormatSeconds(t) + " s (" + std::to_string(t) +
                           " ns) is outside the span of " + trajectory_file + ", " + span +
                           " (no extrapolation)");
    }
    // T_M_C = T_M_W * T_W_F(t) * T_F_C (see the header).
    poses.push_back(placement.T_map_world * *T_world_frame * placement.T_frame_camera);
  }
  return poses;
}

}  // namespace uf::pipeline
