// Camera intrinsics in YAML, in the EuRoC / Kalibr vocabulary: the one dialect of the project's files
// (EuRoC's sensor.yaml, the `calibration` of dataset.yaml, the cameras of a calibration file and the camera
// file of `ultrafusion render`, calibration_file.h):
//   camera_model: pinhole                        # optional, the only model
//   distortion_model: radial-tangential | equidistant
//   intrinsics: [fx, fy, cx, cy]                 # pixels; pixel (0, 0) is the centre of the top-left pixel
//   distortion_coefficients: [k1, k2, p1, p2] (radial-tangential; a fifth, k3, is allowed)
//                            [k1, k2, k3, k4]     (equidistant)
//   resolution: [width, height]                  # pixels
// Camera axes as OpenCV: x right, y down, z forward. Internal to uf_io.
#pragma once

#include <yaml-cpp/yaml.h>

#include <memory>
#include <string>

#include "odometry/types/camera_model.h"
#include "odometry/types/status.h"

namespace uf {

// The keys above, for unknown-key checks.
inline constexpr const char* kCameraCalibrationKeys[] = {"camera_model", "distortion_model", "intrinsics",
                                                         "distortion_coefficients", "resolution"};

// The camera model the keys of `node` describe (other keys are left to the caller). Errors start with
// `where` and name the key, its line and the value ("cam0/sensor.yaml: intrinsics (line 4): needs 4
// numbers (fx, fy, cx, cy), found '[458.6, 457.3]'"), or the impossible intrinsics.
Expected<std::shared_ptr<const CameraModel>> ParseCameraCalibration(const YAML::Node& node,
                                                                    const std::string& where);

// Writes the keys above for `model` into an open map.
void EmitCameraCalibration(YAML::Emitter& yaml, const CameraModel& model);

}  // namespace uf
