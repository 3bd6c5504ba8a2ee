#include "splat/render_types.h"

#include <cmath>
#include <sstream>

namespace uf::splat {

Status SplatCamera::Validate() const {
  const auto& [width, height, fx, fy, cx, cy] = pinhole;
  std::ostringstream message;
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    message << "image size must be in [1, 16384] px, got " << width << " x " << height;
  else if (!(std::isfinite(fx) && fx > 0) || !(std::isfinite(fy) && fy > 0))
    message << "focal lengths must be positive and finite, got fx " << fx << ", fy " << fy;
  else if (!std::isfinite(cx) || !std::isfinite(cy))
    message << "principal point must be finite, got cx " << cx << ", cy " << cy;
  else if (!T_world_camera.matrix().allFinite())
    message << "camera pose is not finite";
  else
    return Status();
  return Status::Error(message.str());
}

RenderedView RenderedView::Sized(int width, int height) {
  RenderedView view;
  view.width = width;
  view.height = height;
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  view.rgb.assign(3 * pixels, 0.0f);
  view.alpha.assign(pixels, 0.0f);
  view.depth.assign(pixels, kNoDepth);
  view.expected_depth.assign(pixels, kNoDepth);
  return view;
}

}  // namespace uf::splat
