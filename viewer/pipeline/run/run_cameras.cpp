#include "viewer/pipeline/run/run_cameras.h"

namespace uf::pipeline {

namespace fs = std::filesystem;

Calibration PlacedCameras(const DatasetDescription& description, const std::vector<Stamp>& time_offsets) {
  Calibration cameras;
  cameras.body_frame = "dataset body";
  for (std::size_t s = 0; s < description.streams.size(); ++s) {
    const StreamInfo& stream = description.streams[s];
    if (stream.kind != SensorKind::kCamera || !stream.camera_model || !stream.T_body_sensor) continue;
    cameras.sensors.push_back({.name = stream.name,
                               .kind = SensorKind::kCamera,
                               .T_body_sensor = *stream.T_body_sensor,
                               .time_offset = s < time_offsets.size() ? time_offsets[s] : 0,
                               .camera_model = stream.camera_model});
  }
  return cameras;
}

Status WriteRunCameras(const fs::path& folder, const Calibration& cameras) {
  const fs::path file = folder / kRunCamerasFile;
  if (cameras.sensors.empty()) {
    std::error_code error;
    fs::remove(file, error);
    return {};
  }
  return WriteCalibrationFile(file, cameras,
                              "The cameras of the run's dataset (docs/ARCHITECTURE.md, \"The run folder\"):\n"
                              "T_body_sensor in the dataset's body frame, which run.json's\n"
                              "frames.T_output_body takes to the frame of trajectory.tum.");
}

Expected<Calibration> ReadRunCameras(const fs::path& folder) {
  const fs::path file = folder / kRunCamerasFile;
  std::error_code error;
  if (!fs::exists(file, error))
    return Status::Error(
        file.string() +
        ": missing; `ultrafusion run` writes it when the dataset has a camera with intrinsics "
        "and an extrinsic (runs made before it was written have none: run again)");
  return ReadCalibrationFile(file);
}

Expected<SensorCalibration> FindRunCamera(const Calibration& cameras, const std::string& name,
                                          const fs::path& folder) {
  const std::string file = (folder / kRunCamerasFile).string();
  std::string names;
  for (const SensorCalibration& camera : cameras.sensors) {
    if (camera.kind != SensorKind::kCamera || !camera.camera_model) continue;
    if (name.empty() || camera.name == name) return camera;
    names += (names.empty() ? "" : ", ") + camera.name;
  }
  if (names.empty()) return Status::Error(file + ": no camera with intrinsics");
  return Status::Error("--camera " + name + ": no such camera in " + file + " (cameras: " + names + ")");
}

}  // namespace uf::pipeline
