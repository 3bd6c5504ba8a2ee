// Splat views as a real camera sees them, lens distortion included: the one way `ultrafusion render` and
// run's views stage render a trained model through a dataset's or a file's camera model.
//
// Splats project through a pinhole (their EWA footprint needs a linear projection), so:
//  - a camera without distortion (PinholeRadtan with all coefficients zero) is rendered through its own
//    pinhole, PinholeOf(model) (training_images.h), at T_world_camera;
//  - a distorted one (any coefficient non-zero, or a fisheye) is rendered through the covering pinhole of
//    DistortedViewResampler (distorted_view.h) at the same pose, then resampled to the model's image, with
//    the render's background for the rays outside the covering pinhole image.
// The renderer itself is a parameter (SplatRenderer::Render, or RenderReference on the CPU), so the same
// function serves the Vulkan renderer and the tests.
#pragma once

#include <functional>
#include <optional>

#include "odometry/types/camera_model.h"
#include "odometry/types/pinhole_intrinsics.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"
#include "splat/render_types.h"
#include "splat/views/distorted_view.h"

namespace uf::splat {

class CameraViewRenderer {
 public:
  // Renders the pinhole camera it is given with the settings it is given.
  using PinholeRender = std::function<Expected<RenderedView>(const SplatCamera&, const RenderSettings&)>;

  // Errors: a camera model other than PinholeRadtan or Equidistant.
  static Expected<CameraViewRenderer> Create(const CameraModel& model);

  // The view of the camera at T_world_camera, of the model's size: `render` renders the pinhole camera (see
  // the top of this file) with `settings`; its error is returned as it is.
  Expected<RenderedView> Render(const SE3& T_world_camera, const RenderSettings& settings,
                                const PinholeRender& render) const;

  bool distorted() const { return resampler_.has_value(); }

 private:
  explicit CameraViewRenderer(const PinholeIntrinsics& pinhole) : pinhole_(pinhole) {}

  PinholeIntrinsics pinhole_;                        // the model's own
  std::optional<DistortedViewResampler> resampler_;  // distorted models only
};

}  // namespace uf::splat
