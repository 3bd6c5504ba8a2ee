// Views for cameras with lens distortion. Splats project through a pinhole (their EWA footprint needs a
// linear projection), so a distorted view is rendered in two steps: through a pinhole camera with the same
// focal lengths whose image covers every ray of the distorted image, then resampled: distorted pixel p has
// bearing b = Unproject(p) and pinhole position (fx b_x / b_z + cx', fy b_y / b_z + cy'). Colour and alpha
// are interpolated bilinearly; the depth channels take the nearest pinhole pixel (interpolating across an
// occlusion edge would invent surfaces). Both depths are along the optical axis, which the two cameras share.
// Renderers use it through CameraViewRenderer (camera_view_renderer.h).
#pragma once

#include <vector>

#include "odometry/types/camera_model.h"
#include "odometry/types/pinhole_intrinsics.h"
#include "splat/render_types.h"

namespace uf::splat {

class DistortedViewResampler {
 public:
  // pinhole: the model's focal lengths and principal point (PinholeOf, training_images.h; its size is the
  // model's). The pinhole image spans at most max_scale times the distorted one per side around the principal
  // point (strong wide-angle distortion would ask for a huge pinhole image; rays beyond stay background).
  DistortedViewResampler(const CameraModel& model, const PinholeIntrinsics& pinhole, double max_scale = 3.0);

  // The pinhole camera to render, at pose T_world_camera.
  SplatCamera Pinhole(const SE3& T_world_camera) const;
  // The distorted view from the rendered pinhole view; `background` fills rays outside the pinhole image.
  RenderedView Resample(const RenderedView& pinhole, const Eigen::Vector3f& background) const;

 private:
  int width_, height_;        // distorted image
  SplatCamera pinhole_;       // intrinsics and size of the covering pinhole image
  std::vector<float> u_, v_;  // per distorted pixel: its position in the pinhole image (NaN: no ray)
};

}  // namespace uf::splat
