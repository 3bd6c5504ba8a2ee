#include "mapping/colorizer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

namespace uf::mapping {
namespace {

std::string SizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

std::uint8_t ToByte(float value) { return static_cast<std::uint8_t>(std::clamp(value, 0.0f, 255.0f) + 0.5f); }

}  // namespace

Status ValidateColorizerOptions(const ColorizerOptions& options) {
  if (Status s = ValidateVisibilityOptions(options.visibility, "colorizer.visibility"); !s.ok()) return s;
  if (!(options.max_time_difference_s > 0) || !std::isfinite(options.max_time_difference_s)) {
    std::ostringstream text;
    text << "colorizer.max_time_difference_s: must be positive and finite, got "
         << options.max_time_difference_s;
    return Status::Error(text.str());
  }
  return Status();
}

Status CheckCameraView(const CameraView& view) {
  assert(view.image != nullptr && view.camera != nullptr);
  const Image& image = *view.image;
  if (image.empty() || image.width <= 0 || image.height <= 0) return Status::Error("image: empty");
  if (image.channels != 1 && image.channels != 3)
    return Status::Error("image: expected 1 (gray) or 3 (RGB) channels, got " +
                         std::to_string(image.channels));
  if (image.pixels.size() !=
      static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * image.channels)
    return Status::Error("image: pixel buffer size does not match " + SizeText(image.width, image.height));
  if (image.width != view.camera->width() || image.height != view.camera->height())
    return Status::Error("image: size " + SizeText(image.width, image.height) +
                         " differs from the camera's " +
                         SizeText(view.camera->width(), view.camera->height()));
  return Status();
}

Eigen::Vector3f SampleBilinear(const Image& image, const Eigen::Vector2f& pixel) {
  // c(u, v) = sum over the four pixel centres (u0 + i, v0 + j) of c_ij (1 - |u - u0 - i|)(1 - |v - v0 - j|).
  const float u = std::clamp(pixel.x(), 0.0f, static_cast<float>(image.width - 1));
  const float v = std::clamp(pixel.y(), 0.0f, static_cast<float>(image.height - 1));
  const int u0 = std::min(static_cast<int>(u), std::max(0, image.width - 2));
  const int v0 = std::min(static_cast<int>(v), std::max(0, image.height - 2));
  const int u1 = std::min(u0 + 1, image.width - 1), v1 = std::min(v0 + 1, image.height - 1);
  const float fu = u - static_cast<float>(u0), fv = v - static_cast<float>(v0);
  const auto texel = [&](int x, int y) {
    const std::size_t i =
        (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) *
        static_cast<std::size_t>(image.channels);
    if (image.channels == 1) return Eigen::Vector3f::Constant(image.pixels[i]).eval();
    return Eigen::Vector3f(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]);
  };
  return (1 - fv) * ((1 - fu) * texel(u0, v0) + fu * texel(u1, v0)) +
         fv * ((1 - fu) * texel(u0, v1) + fu * texel(u1, v1));
}

Expected<ColorizeResult> Colorize(std::span<const Eigen::Vector3f> points_world,
                                  std::span<const Stamp> point_stamps, std::span<const CameraView> views,
                                  const ColorizerOptions& options) {
  assert(point_stamps.size() == 1 || point_stamps.size() == points_world.size());
  if (Status s = ValidateColorizerOptions(options); !s.ok()) return s;
  for (std::size_t k = 0; k < views.size(); ++k) {
    if (Status s = CheckCameraView(views[k]); !s.ok())
      return Status::Error("view " + std::to_string(k) + ": " + s.message());
  }
  const std::size_t n = points_world.size();
  const auto stamp_of = [&](std::size_t i) {
    return point_stamps.size() == 1 ? point_stamps[0] : point_stamps[i];
  };
  const Stamp max_gap = FromSeconds(options.max_time_difference_s);

  // Per point, the best view so far: (time difference, off-axis tangent), compared lexicographically.
  ColorizeResult result;
  result.colors.assign(n, std::nullopt);
  result.view_index.assign(n, -1);
  std::vector<Stamp> best_gap(n, std::numeric_limits<Stamp>::max());
  std::vector<float> best_off_axis(n, std::numeric_limits<float>::infinity());
  std::vector<std::uint8_t> in_footprint(n, 0);
  for (std::size_t k = 0; k < views.size(); ++k) {
    const CameraView& view = views[k];
    const ProjectedScan scan =
        ProjectWithOcclusion(points_world, *view.camera, view.T_world_cam, options.visibility);
    for (std::size_t i = 0; i < n; ++i) {
      const ProjectedPoint& p = scan.points[i];
      if (p.visibility == PointVisibility::kOutside) continue;
      const Stamp gap = std::abs(view.stamp - stamp_of(i));
      if (gap > max_gap) continue;
      in_footprint[i] = 1;
      if (p.visibility != PointVisibility::kVisible) continue;
      if (gap > best_gap[i] || (gap == best_gap[i] && p.off_axis_tan >= best_off_axis[i])) continue;
      best_gap[i] = gap;
      best_off_axis[i] = p.off_axis_tan;
      result.view_index[i] = static_cast<int>(k);
      const Eigen::Vector3f rgb = SampleBilinear(*view.image, p.pixel);
      result.colors[i] = Rgb{ToByte(rgb.x()), ToByte(rgb.y()), ToByte(rgb.z())};
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    result.in_footprint += in_footprint[i];
    result.colored += result.colors[i].has_value() ? 1 : 0;
  }
  result.occluded = result.in_footprint - result.colored;
  return result;
}

}  // namespace uf::mapping
