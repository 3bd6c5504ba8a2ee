// Camera intrinsics in dataset files, in the EuRoC / Kalibr vocabulary that both EuRoC's sensor.yaml and
// the project's dataset.yaml use:
//   distortion_model: radial-tangential | equidistant
//   intrinsics: [fx, fy, cx, cy]                 # pixels
//   distortion_coefficients: [k1, k2, p1, p2] (radial-tangential; a fifth, k3, is allowed)
//                            [k1, k2, k3, k4]     (equidistant)
//   resolution: [width, height]
// (EuRoC's `camera_model: pinhole` is accepted and is the only model.) Internal to uf_io.
#pragma once

#include <yaml-cpp/yaml.h>

#include <memory>
#include <string>

#include "odometry/types/camera_model.h"
#include "odometry/types/status.h"

namespace uf {

// The camera model the keys of `node` describe; errors start with `where` and name the key and value.
// Throws YAML exceptions for values of the wrong type (the callers turn those into errors).
Expected<std::shared_ptr<const CameraModel>> ParseCameraCalibration(const YAML::Node& node,
                                                                    const std::string& where);

// Writes the keys above for `model` into an open map.
void EmitCameraCalibration(YAML::Emitter& yaml, const CameraModel& model);

}  // namespace uf
