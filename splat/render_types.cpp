#include "splat/render_types.h"

#include <cmath>
#include <sstream>
#include <string>

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

Status ValidateRenderSettings(const RenderSettings& s) {
  auto error = [](const std::string& field, const std::string& rule, float value) {
    return Status::Error("render settings: " + field + " must be " + rule + ", got " + std::to_string(value));
  };
  if (!(std::isfinite(s.near) && s.near > 0)) return error("near", "positive and finite", s.near);
  if (!(s.low_pass >= 0 && std::isfinite(s.low_pass)))
    return error("low_pass", ">= 0 and finite", s.low_pass);
  if (!(s.max_alpha > 0 && s.max_alpha <= 1)) return error("max_alpha", "in (0, 1]", s.max_alpha);
  if (!(s.min_alpha >= 0 && s.min_alpha < s.max_alpha))
    return error("min_alpha", "in [0, max_alpha)", s.min_alpha);
  if (!(s.transmittance_cutoff >= 0 && s.transmittance_cutoff < 1))
    return error("transmittance_cutoff", "in [0, 1)", s.transmittance_cutoff);
  if (!s.background.allFinite()) return error("background", "finite", s.background.norm());
  return Status();
}

}  // namespace uf::splat
