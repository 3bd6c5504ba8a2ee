#include "viewer/pipeline/run_render_inputs.h"

#include "odometry/io/trajectory_file.h"
#include "viewer/pipeline/run/run_camera_poses.h"
#include "viewer/pipeline/run/run_cameras.h"
#include "viewer/pipeline/run/run_record.h"
#include "viewer/pipeline/splat/splat_run_inputs.h"

namespace uf::pipeline {

namespace fs = std::filesystem;

Expected<RenderInputs> ReadRunRenderInputs(const fs::path& folder, const std::string& stamps_file,
                                           const std::string& camera) {
  Expected<RunRecord> record = ReadRunRecord(folder);
  if (!record) return record.status();
  RenderInputs inputs;
  inputs.splats = folder / "splats.ply";
  std::error_code error;
  if (!fs::exists(inputs.splats, error))
    return Status::Error(inputs.splats.string() +
                         ": missing; the run trained no splats (run `ultrafusion splat` on the folder, or "
                         "`ultrafusion run` with a camera and without --no-splat)");
  Expected<Calibration> cameras = ReadRunCameras(folder);
  if (!cameras) return cameras.status();
  Expected<SensorCalibration> chosen = FindRunCamera(*cameras, camera, folder);
  if (!chosen) return chosen.status();
  inputs.camera_name = chosen->name;
  inputs.camera = chosen->camera_model;

  const fs::path trajectory_file = folder / "trajectory.tum";
  Expected<Trajectory> trajectory = ReadSplatTrajectory(trajectory_file);
  if (!trajectory) return trajectory.status();
  Expected<std::vector<Stamp>> stamps = ReadStampsFile(stamps_file);
  if (!stamps) return stamps.status();
  const RunFrames& frames = record->frames;
  const CameraPlacement placement{.T_map_world = frames.T_map_world,
                                  .T_frame_camera = frames.T_output_body * chosen->T_body_sensor};
  Expected<std::vector<SE3>> poses =
      CameraPosesAt(*trajectory, placement, *stamps, trajectory_file.string(), stamps_file);
  if (!poses) return poses.status();
  inputs.stamps = std::move(*stamps);
  inputs.T_world_camera = std::move(*poses);
  return inputs;
}

}  // namespace uf::pipeline
