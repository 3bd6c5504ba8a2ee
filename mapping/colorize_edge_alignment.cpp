#include "mapping/colorize_edge_alignment.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>
#include <string>

namespace uf::mapping {
namespace {

template <typename T>
Status RangeError(const std::string& field, const std::string& range, T value) {
  std::ostringstream text;
  text << "edge_alignment." << field << ": must be " << range << ", got " << value;
  return Status::Error(text.str());
}

// Grey level (ITU-R BT.601 luma) of every pixel.
std::vector<float> Grey(const Image& image) {
  const std::size_t count = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  std::vector<float> grey(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (image.channels == 1) {
      grey[i] = image.pixels[i];
    } else {
      const std::uint8_t* p = &image.pixels[3 * i];
      grey[i] = 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
    }
  }
  return grey;
}

// Sobel gradient magnitude: gu = [-1 0 1; -2 0 2; -1 0 1] * grey, gv its transpose, E = sqrt(gu^2 + gv^2);
// zero on the one-pixel border.
std::vector<float> SobelMagnitude(const std::vector<float>& grey, int width, int height) {
  std::vector<float> edges(grey.size(), 0.0f);
  const auto g = [&](int u, int v) { return grey[static_cast<std::size_t>(v) * width + u]; };
  for (int v = 1; v + 1 < height; ++v) {
    for (int u = 1; u + 1 < width; ++u) {
      const float gu = (g(u + 1, v - 1) + 2 * g(u + 1, v) + g(u + 1, v + 1)) -
                       (g(u - 1, v - 1) + 2 * g(u - 1, v) + g(u - 1, v + 1));
      const float gv = (g(u - 1, v + 1) + 2 * g(u, v + 1) + g(u + 1, v + 1)) -
                       (g(u - 1, v - 1) + 2 * g(u, v - 1) + g(u + 1, v - 1));
      edges[static_cast<std::size_t>(v) * width + u] = std::sqrt(gu * gu + gv * gv);
    }
  }
  return edges;
}

// In place, along `count` values `step` apart: x_i <- max_j x_j decay^|i - j|, exactly, by a forward sweep
// f_i = max(x_i, decay f_(i-1)) and a backward one b_i = max(f_i, decay b_(i+1)).
void DecayingMax(float* values, int count, std::ptrdiff_t step, float decay) {
  for (int i = 1; i < count; ++i)
    values[i * step] = std::max(values[i * step], decay * values[(i - 1) * step]);
  for (int i = count - 2; i >= 0; --i)
    values[i * step] = std::max(values[i * step], decay * values[(i + 1) * step]);
}

}  // namespace

Status ValidateEdgeAlignmentOptions(const EdgeAlignmentOptions& options) {
  if (options.edge_spread_px < 1 || options.edge_spread_px > 64)
    return RangeError("edge_spread_px", "in [1, 64]", options.edge_spread_px);
  if (options.edge_window_px < 1 || options.edge_window_px > 256)
    return RangeError("edge_window_px", "in [1, 256]", options.edge_window_px);
  if (options.edge_rows_px < 0 || options.edge_rows_px > 16)
    return RangeError("edge_rows_px", "in [0, 16]", options.edge_rows_px);
  if (!(options.min_depth_jump_m >= 0) || !std::isfinite(options.min_depth_jump_m))
    return RangeError("min_depth_jump_m", "finite and >= 0", options.min_depth_jump_m);
  if (!(options.min_depth_jump_ratio >= 0) || !std::isfinite(options.min_depth_jump_ratio))
    return RangeError("min_depth_jump_ratio", "finite and >= 0", options.min_depth_jump_ratio);
  return ValidateVisibilityOptions(options.visibility, "edge_alignment.visibility");
}

EdgeAlignmentScorer::EdgeAlignmentScorer(const Image& image, const EdgeAlignmentOptions& options)
    : options_(options), width_(image.width), height_(image.height) {
  assert(!image.empty() && (image.channels == 1 || image.channels == 3));
  spread_ = SobelMagnitude(Grey(image), width_, height_);
  // S = max_y E(y) g^(|du| + |dv|): the decaying max along rows, then along columns (separable because
  // g^(|du| + |dv|) = g^|du| g^|dv|).
  const auto decay = static_cast<float>(std::exp2(-1.0 / options_.edge_spread_px));
  for (int v = 0; v < height_; ++v)
    DecayingMax(&spread_[static_cast<std::size_t>(v) * width_], width_, 1, decay);
  for (int u = 0; u < width_; ++u) DecayingMax(&spread_[static_cast<std::size_t>(u)], height_, width_, decay);
}

float EdgeAlignmentScorer::Spread(const Eigen::Vector2f& pixel) const {
  // Bilinear between the four nearest pixel centres, clamped at the border.
  const float u = std::clamp(pixel.x(), 0.0f, static_cast<float>(width_ - 1));
  const float v = std::clamp(pixel.y(), 0.0f, static_cast<float>(height_ - 1));
  const int u0 = std::min(static_cast<int>(u), std::max(0, width_ - 2));
  const int v0 = std::min(static_cast<int>(v), std::max(0, height_ - 2));
  const int u1 = std::min(u0 + 1, width_ - 1), v1 = std::min(v0 + 1, height_ - 1);
  const float fu = u - static_cast<float>(u0), fv = v - static_cast<float>(v0);
  const auto s = [&](int x, int y) { return spread_[static_cast<std::size_t>(y) * width_ + x]; };
  return (1 - fv) * ((1 - fu) * s(u0, v0) + fu * s(u1, v0)) + fv * ((1 - fu) * s(u0, v1) + fu * s(u1, v1));
}

std::vector<bool> FindDepthEdges(const ProjectedScan& scan, int width, int height,
                                 const EdgeAlignmentOptions& options) {
  // Farthest visible depth per pixel (0: no point there).
  std::vector<float> farthest(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0f);
  const auto pixel_of = [&](const ProjectedPoint& p) {
    return Eigen::Vector2i(std::clamp(static_cast<int>(std::lround(p.pixel.x())), 0, width - 1),
                           std::clamp(static_cast<int>(std::lround(p.pixel.y())), 0, height - 1));
  };
  for (const ProjectedPoint& p : scan.points) {
    if (p.visibility != PointVisibility::kVisible) continue;
    const Eigen::Vector2i q = pixel_of(p);
    float& d = farthest[static_cast<std::size_t>(q.y()) * width + q.x()];
    d = std::max(d, p.depth);
  }
  std::vector<bool> edges(scan.points.size(), false);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const ProjectedPoint& p = scan.points[i];
    if (p.visibility != PointVisibility::kVisible) continue;
    const Eigen::Vector2i q = pixel_of(p);
    const float jump = std::max(static_cast<float>(options.min_depth_jump_m),
                                static_cast<float>(options.min_depth_jump_ratio) * p.depth);
    // Farthest visible depth along the row band and along the column band.
    float neighbour = 0.0f;
    const auto scan_band = [&](int u0, int u1, int v0, int v1) {
      for (int v = std::max(0, v0); v <= std::min(height - 1, v1); ++v) {
        const float* row = &farthest[static_cast<std::size_t>(v) * width];
        for (int u = std::max(0, u0); u <= std::min(width - 1, u1); ++u)
          neighbour = std::max(neighbour, row[u]);
      }
    };
    const int w = options.edge_window_px, r = options.edge_rows_px;
    scan_band(q.x() - w, q.x() + w, q.y() - r, q.y() + r);
    scan_band(q.x() - r, q.x() + r, q.y() - w, q.y() + w);
    edges[i] = neighbour - p.depth > jump;
  }
  return edges;
}

EdgeAlignment EdgeAlignmentScorer::Score(const ProjectedScan& scan) const {
  const std::vector<bool> edges = FindDepthEdges(scan, width_, height_, options_);
  double sum_all = 0.0, sum_edges = 0.0;
  EdgeAlignment result;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const ProjectedPoint& p = scan.points[i];
    if (p.visibility != PointVisibility::kVisible) continue;
    const double s = Spread(p.pixel);
    sum_all += s;
    ++result.visible_points;
    if (!edges[i]) continue;
    sum_edges += s;
    ++result.edge_points;
  }
  if (result.edge_points > 0 && sum_all > 0.0) {
    result.score = (sum_edges / static_cast<double>(result.edge_points)) /
                   (sum_all / static_cast<double>(result.visible_points));
  }
  return result;
}

EdgeAlignment EdgeAlignmentScorer::Score(std::span<const Eigen::Vector3f> points_world,
                                         const CameraModel& camera, const SE3& T_world_cam) const {
  assert(camera.width() == width_ && camera.height() == height_);
  return Score(ProjectWithOcclusion(points_world, camera, T_world_cam, options_.visibility));
}

}  // namespace uf::mapping
