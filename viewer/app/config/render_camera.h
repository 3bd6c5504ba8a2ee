// The camera file of `ultrafusion render`: a small YAML map
//   model: pinhole            # the only model
//   width: 640                # px
//   height: 480
//   fx: 525.0                 # px
//   fy: 525.0
//   cx: 319.5                 # px; pixel (0, 0) is the centre of the top-left pixel
//   cy: 239.5
//   distortion: [k1, k2, p1, p2]   # optional, radial-tangential (OpenCV's plumb bob); a fifth, k3, is
//   allowed
// Camera axes as OpenCV: x right, y down, z forward. Unknown keys are an error that names them.
#pragma once

#include <memory>
#include <string>

#include "odometry/types/camera_model.h"
#include "odometry/types/status.h"

namespace uf::app {

struct RenderCamera {
  PinholeRadtanIntrinsics intrinsics;
  int width = 0, height = 0;
  bool distorted = false;                      // any distortion coefficient non-zero
  std::shared_ptr<const PinholeRadtan> model;  // the full model (always set)
};

// Reads and checks the file; errors name the file, the key and the value (impossible intrinsics included).
Expected<RenderCamera> LoadRenderCamera(const std::string& path);

// The camera for a different output size: intrinsics scaled by width/width0 and height/height0 (the image
// plane stretches; pixel centres stay at integer coordinates: c' = (c + 0.5) s - 0.5).
RenderCamera ResizeRenderCamera(const RenderCamera& camera, int width, int height);

}  // namespace uf::app
