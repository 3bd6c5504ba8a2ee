#include "viewer/pipeline/colorize/colorize_overlay.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace uf::pipeline {

DepthRange VisibleDepthRange(const mapping::ProjectedScan& scan) {
  std::vector<float> depths;
  for (const mapping::ProjectedPoint& p : scan.points)
    if (p.visibility == mapping::PointVisibility::kVisible) depths.push_back(p.depth);
  if (depths.empty()) return {};
  const auto at = [&](double fraction) {
    auto nth = depths.begin() + std::ptrdiff_t(fraction * double(depths.size() - 1));
    std::nth_element(depths.begin(), nth, depths.end());
    return *nth;
  };
  return {at(0.05), at(0.95)};
}

std::array<std::uint8_t, 3> DepthColor(float depth, const DepthRange& range) {
  const float span = range.far_m - range.near_m;
  const float t = span > 0 ? std::clamp((depth - range.near_m) / span, 0.0f, 1.0f) : 0.0f;
  // HSV -> RGB with S = V = 1: the hue h in [0, 240] deg falls in sector i = floor(h / 60) with fraction
  // f = h / 60 - i; the rising channel is f, the falling one 1 - f.
  const float h = 4.0f * t;  // hue / 60 deg, in [0, 4]
  const int sector = std::min(int(h), 3);
  const float f = h - float(sector);
  float r = 0, g = 0, b = 0;
  switch (sector) {
    case 0:
      r = 1, g = f;
      break;  // red -> yellow
    case 1:
      r = 1 - f, g = 1;
      break;  // yellow -> green
    case 2:
      g = 1, b = f;
      break;  // green -> cyan
    default:
      g = 1 - f, b = 1;
      break;  // cyan -> blue
  }
  const auto byte = [](float v) { return std::uint8_t(std::lround(255.0f * v)); };
  return {byte(r), byte(g), byte(b)};
}

Image RenderDepthOverlay(const Image& image, const mapping::ProjectedScan& scan, const DepthRange& range) {
  Image overlay;
  overlay.width = image.width;
  overlay.height = image.height;
  overlay.channels = 3;
  overlay.pixels.resize(std::size_t(image.width) * image.height * 3);
  for (std::size_t i = 0, n = std::size_t(image.width) * image.height; i < n; ++i)
    for (int c = 0; c < 3; ++c) overlay.pixels[3 * i + c] = image.pixels[image.channels == 3 ? 3 * i + c : i];

  std::vector<std::size_t> visible;
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    if (scan.points[i].visibility == mapping::PointVisibility::kVisible) visible.push_back(i);
  std::stable_sort(visible.begin(), visible.end(),
                   [&](std::size_t a, std::size_t b) { return scan.points[a].depth > scan.points[b].depth; });
  const int r = std::max(1, int(std::lround(image.width / 1000.0)));
  for (const std::size_t i : visible) {
    const mapping::ProjectedPoint& p = scan.points[i];
    const std::array<std::uint8_t, 3> color = DepthColor(p.depth, range);
    // Pixel centres are integers: the point's pixel is the nearest one.
    const int u = int(std::lround(p.pixel.x())), v = int(std::lround(p.pixel.y()));
    for (int y = std::max(0, v - r); y <= std::min(image.height - 1, v + r); ++y)
      for (int x = std::max(0, u - r); x <= std::min(image.width - 1, u + r); ++x)
        std::copy(color.begin(), color.end(),
                  overlay.pixels.begin() + 3 * (std::ptrdiff_t(y) * image.width + x));
  }
  return overlay;
}

}  // namespace uf::pipeline
