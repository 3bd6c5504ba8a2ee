// The camera file of `ultrafusion render SPLATS --camera FILE`: one camera's intrinsics in the dialect of the
// calibration files, read by their parser (odometry/io/camera_calibration.h; the keys are in docs/CONFIG.md,
// "Camera intrinsics"). Render draws pinhole cameras with radial-tangential distortion; camera axes as
// OpenCV: x right, y down, z forward.
#pragma once

#include <memory>
#include <string>

#include "odometry/types/camera_model.h"
#include "odometry/types/status.h"

namespace uf::app {

struct RenderCamera {
  PinholeRadtanIntrinsics intrinsics;          // size, fx, fy, cx, cy and distortion
  bool distorted = false;                      // any distortion coefficient non-zero
  std::shared_ptr<const PinholeRadtan> model;  // the full model (always set)
};

// Reads and checks the file; errors name the file, the key and the value (impossible intrinsics included).
Expected<RenderCamera> LoadRenderCamera(const std::string& path);

// `model` for a different output size: the pinhole scaled about pixel corners (splat::ScalePinhole:
// f' = f s, c' = (c + 0.5) s - 0.5 with s = width/width0 or height/height0), the distortion kept.
// PinholeRadtan and Equidistant; another model is an error.
Expected<std::shared_ptr<const CameraModel>> ResizeCameraModel(const CameraModel& model, int width,
                                                               int height);

}  // namespace uf::app
