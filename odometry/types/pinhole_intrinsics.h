// The pinhole part of a camera: image size, focal lengths and principal point, in pixels. Camera axes as
// OpenCV (x right, y down, z forward): a camera-frame point t projects to
//   (u, v) = (fx t_x / t_z + cx, fy t_y / t_z + cy),
// and pixel (x, y) is centred at (u, v) = (x, y), so (0, 0) is the centre of the top-left pixel and the image
// spans [-0.5, width - 0.5] x [-0.5, height - 0.5].
//
// The one pinhole type of the project: the camera models add their distortion to it (camera_model.h), the
// splat renderers render through it (splat/render_types.h, SplatCamera), and the simulated camera is
// configured with it (odometry/sim/sensors/camera_renderer.h).
#pragma once

namespace uf {

struct PinholeIntrinsics {
  int width = 0, height = 0;              // px
  double fx = 0, fy = 0, cx = 0, cy = 0;  // px

  bool operator==(const PinholeIntrinsics&) const = default;
};

}  // namespace uf
