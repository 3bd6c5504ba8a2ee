#include "mapping/colorize_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace uf::mapping {
namespace {

constexpr int kMaxSplatHalfSize = 32;
constexpr int kMaxGapSearchPx = 64;
constexpr float kSameSurfaceMinM = 0.3f, kSameSurfaceRatio = 0.1f;  // neighbours of the same surface

std::string Describe(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// Nearest integer pixel of a pixel coordinate inside the image (InImage allows half a pixel outside).
int PixelIndex(float coordinate, int size) {
  return std::clamp(static_cast<int>(std::lround(coordinate)), 0, size - 1);
}

// The block a point's depth is written to: pixels [u - left, u + right] x [v - up, v + down], with the
// inverse depth changing by step_* per pixel in each direction (0: the point's own depth over the block).
struct Splat {
  int left = 0, right = 0, up = 0, down = 0;
  float step_left = 0, step_right = 0, step_up = 0, step_down = 0;  // 1/m per pixel

  // The depth written at pixel offset (dx, dy) from the point at `depth`: 1/z = 1/depth + |dx| step_x +
  // |dy| step_y (step_x, step_y those of the side the offset lies on); infinite where that leaves the
  // camera's front.
  float DepthAt(float depth, int dx, int dy) const {
    const float inverse = 1 / depth + static_cast<float>(std::abs(dx)) * (dx < 0 ? step_left : step_right) +
                          static_cast<float>(std::abs(dy)) * (dy < 0 ? step_up : step_down);
    return inverse > 0 ? 1 / inverse : std::numeric_limits<float>::infinity();
  }
};

// Nearest depth per pixel of the projected points, and the automatic splat of each point (see the header).
class DepthGrid {
 public:
  DepthGrid(int width, int height)
      : width_(width),
        height_(height),
        depth_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
               std::numeric_limits<float>::infinity()) {}

  float& at(int u, int v) {
    return depth_[static_cast<std::size_t>(v) * width_ + static_cast<std::size_t>(u)];
  }
  float at(int u, int v) const {
    return depth_[static_cast<std::size_t>(v) * width_ + static_cast<std::size_t>(u)];
  }

  // The nearest same-surface point from (u, v) along (du, dv), within +-1 pixel across from 3 pixels on:
  // its distance in pixels (0 if none) and the change of inverse depth per pixel towards it.
  struct Neighbour {
    int gap = 0;
    float inverse_depth_step = 0;  // 1/m per pixel
  };
  Neighbour Nearest(int u, int v, int du, int dv, float depth) const {
    const float same = std::max(kSameSurfaceMinM, kSameSurfaceRatio * depth);
    for (int g = 1; g <= kMaxGapSearchPx; ++g) {
      const int x0 = u + g * du, y0 = v + g * dv;
      if (x0 < 0 || y0 < 0 || x0 >= width_ || y0 >= height_) return {};
      const int band = g >= 3 ? 1 : 0;  // no diagonal neighbours close by: they belong to this row/column
      for (int across = -band; across <= band; ++across) {
        const int x = x0 + across * dv, y = y0 + across * du;
        if (x >= 0 && y >= 0 && x < width_ && y < height_ && std::abs(at(x, y) - depth) <= same)
          return {g, (1 / at(x, y) - 1 / depth) / static_cast<float>(g)};
      }
    }
    return {};
  }

  // Half-way to the neighbour in each direction, rounded up but short of the neighbour's own pixel
  // (min(ceil(g / 2), g - 1) for a gap of g pixels), so that the blocks of a surface overlap; mirrored
  // where there is no neighbour; at most max_half. The depth written over the block follows the surface:
  // inverse depth is affine in the pixel coordinates on a plane, so it steps by the change towards each
  // neighbour (mirrored with the opposite sign), and a ground or wall seen at a grazing angle does not hide
  // its own farther points under a flat block.
  Splat AutomaticSplat(int u, int v, float depth, int max_half) const {
    const Neighbour left = Nearest(u, v, -1, 0, depth), right = Nearest(u, v, 1, 0, depth);
    const Neighbour up = Nearest(u, v, 0, -1, depth), down = Nearest(u, v, 0, 1, depth);
    const auto half = [max_half](const Neighbour& n) {
      return n.gap == 0 ? -1 : std::min({(n.gap + 1) / 2, n.gap - 1, max_half});
    };
    Splat s{half(left), half(right), half(up), half(down)};
    s.step_left = left.inverse_depth_step, s.step_right = right.inverse_depth_step;
    s.step_up = up.inverse_depth_step, s.step_down = down.inverse_depth_step;
    const auto mirror = [](int& a, int& b, float& step_a, float& step_b) {
      if (a < 0) a = b, step_a = -step_b;
      if (b < 0) b = a, step_b = -step_a;
      a = std::max(a, 0);
      b = std::max(b, 0);
    };
    mirror(s.left, s.right, s.step_left, s.step_right);
    mirror(s.up, s.down, s.step_up, s.step_down);
    return s;
  }

 private:
  int width_, height_;
  std::vector<float> depth_;
};

}  // namespace

Status ValidateVisibilityOptions(const VisibilityOptions& options, const std::string& prefix) {
  for (const auto& [name, value] : {std::pair{"splat_half_width_px", options.splat_half_width_px},
                                    std::pair{"splat_half_height_px", options.splat_half_height_px}}) {
    if (value < -1 || value > kMaxSplatHalfSize)
      return Status::Error(prefix + "." + name + ": must be -1 (automatic) or in [0, 32], got " +
                           std::to_string(value));
  }
  if (options.max_automatic_half_size_px < 0 || options.max_automatic_half_size_px > kMaxSplatHalfSize)
    return Status::Error(prefix + ".max_automatic_half_size_px: must be in [0, 32], got " +
                         std::to_string(options.max_automatic_half_size_px));
  if (!std::isfinite(options.depth_tolerance_m) || options.depth_tolerance_m < 0)
    return Status::Error(prefix + ".depth_tolerance_m: must be finite and >= 0, got " +
                         Describe(options.depth_tolerance_m));
  if (!(options.depth_tolerance_ratio >= 0 && options.depth_tolerance_ratio < 1))
    return Status::Error(prefix + ".depth_tolerance_ratio: must be in [0, 1), got " +
                         Describe(options.depth_tolerance_ratio));
  return Status();
}

ProjectedScan ProjectWithOcclusion(std::span<const Eigen::Vector3f> points_world, const CameraModel& camera,
                                   const SE3& T_world_cam, const VisibilityOptions& options) {
  const int width = camera.width(), height = camera.height();
  const SE3 T_cam_world = T_world_cam.inverse();
  ProjectedScan scan;
  scan.points.resize(points_world.size());

  // 1. Project: p_cam = T_cam_world p_world, pixel = camera model (distortion included).
  for (std::size_t i = 0; i < points_world.size(); ++i) {
    if (!points_world[i].allFinite()) continue;
    const Eigen::Vector3d p_cam = T_cam_world * points_world[i].cast<double>();
    const std::optional<Eigen::Vector2d> pixel = camera.Project(p_cam);
    if (!pixel || !camera.InImage(*pixel)) continue;
    ProjectedPoint& out = scan.points[i];
    out.pixel = pixel->cast<float>();
    out.depth = static_cast<float>(p_cam.z());
    out.off_axis_tan = static_cast<float>(p_cam.head<2>().norm() / p_cam.z());
    out.visibility = PointVisibility::kOccluded;  // until the z-buffer test below
    ++scan.in_image;
  }

  // 2. Nearest depth per pixel, from which the automatic splats find each point's same-surface neighbours.
  DepthGrid nearest(width, height);
  for (const ProjectedPoint& p : scan.points) {
    if (p.visibility == PointVisibility::kOutside) continue;
    float& d = nearest.at(PixelIndex(p.pixel.x(), width), PixelIndex(p.pixel.y(), height));
    d = std::min(d, p.depth);
  }

  // 3. Z-buffer: nearest depth per pixel over every point's splat block.
  DepthGrid zbuffer(width, height);
  for (const ProjectedPoint& p : scan.points) {
    if (p.visibility == PointVisibility::kOutside) continue;
    const int u = PixelIndex(p.pixel.x(), width), v = PixelIndex(p.pixel.y(), height);
    const bool automatic = options.splat_half_width_px < 0 || options.splat_half_height_px < 0;
    Splat s = automatic ? nearest.AutomaticSplat(u, v, p.depth, options.max_automatic_half_size_px) : Splat{};
    if (options.splat_half_width_px >= 0) s.left = s.right = options.splat_half_width_px;
    if (options.splat_half_height_px >= 0) s.up = s.down = options.splat_half_height_px;
    for (int y = std::max(0, v - s.up); y <= std::min(height - 1, v + s.down); ++y) {
      for (int x = std::max(0, u - s.left); x <= std::min(width - 1, u + s.right); ++x)
        zbuffer.at(x, y) = std::min(zbuffer.at(x, y), s.DepthAt(p.depth, x - u, y - v));
    }
  }

  // 4. Visible: within the depth tolerance of the nearest surface at the point's own pixel.
  const auto tolerance_m = static_cast<float>(options.depth_tolerance_m);
  const auto tolerance_ratio = static_cast<float>(options.depth_tolerance_ratio);
  for (ProjectedPoint& p : scan.points) {
    if (p.visibility == PointVisibility::kOutside) continue;
    const float z_min = zbuffer.at(PixelIndex(p.pixel.x(), width), PixelIndex(p.pixel.y(), height));
    if (p.depth <= z_min + std::max(tolerance_m, tolerance_ratio * p.depth)) {
      p.visibility = PointVisibility::kVisible;
      ++scan.visible;
    }
  }
  return scan;
}

}  // namespace uf::mapping
