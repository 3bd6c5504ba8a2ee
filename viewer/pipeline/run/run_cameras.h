// cameras.yaml: the cameras of a run's dataset, written by `ultrafusion run` beside run.json so that a run
// folder alone says where each camera sat and how it projects (`ultrafusion render RUN_DIR --stamps` reads
// it; the dataset may be gone). The calibration file format (odometry/io/calibration_file.h), with every
// camera stream that has intrinsics and an extrinsic, in stream order:
//
//   calibration:
//     body_frame: dataset body          # B of run_frames.h; run.json's frames.T_output_body is T_F_B
//     sensors:
//       - name: cam0                    # the stream name (`render --camera NAME`)
//         kind: camera
//         T_body_sensor: [16 numbers]   # T_B_C, row-major, exact (shortest round-trip digits)
//         time_offset_s: 0.000000000    # the dataset.time_offsets_s the run added to the camera's stamps
//         intrinsics: {...}             # distortion_model, intrinsics, distortion_coefficients, resolution
//
// The camera's stamps after time_offset_s are on the clock of trajectory.tum.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"

namespace uf::pipeline {

inline constexpr const char* kRunCamerasFile = "cameras.yaml";

// The cameras of `description` that can be placed (intrinsics and T_body_sensor), in stream order, each with
// time_offsets[stream] (ns; an empty vector: no offsets).
Calibration PlacedCameras(const DatasetDescription& description, const std::vector<Stamp>& time_offsets);

// Writes folder/cameras.yaml atomically when `cameras` has any; removes an older one when it has none.
Status WriteRunCameras(const std::filesystem::path& folder, const Calibration& cameras);

// Reads folder/cameras.yaml. A folder without one gets an error that says why a run may have none (no
// camera with intrinsics and an extrinsic, or a run made before the file was written).
Expected<Calibration> ReadRunCameras(const std::filesystem::path& folder);

// The camera `name` of the run ("": the first). An unknown name is an error listing the run's cameras.
Expected<SensorCalibration> FindRunCamera(const Calibration& cameras, const std::string& name,
                                          const std::filesystem::path& folder);

}  // namespace uf::pipeline
