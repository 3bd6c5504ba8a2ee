#include "splat/views/training_images.h"

#include <algorithm>
#include <cmath>

namespace uf::splat {
namespace {

// Per target pixel along one axis: the source pixels it overlaps and the overlap lengths, normalised.
// Target pixel i covers source edge coordinates [i / s, (i + 1) / s] with s = n' / n (edge coordinate = pixel
// centre coordinate + 0.5).
struct AxisWeights {
  std::vector<int> first;                  // first source pixel of target pixel i
  std::vector<std::vector<float>> weight;  // weights of source pixels first[i], first[i] + 1, ...
};

AxisWeights BoxWeights(int n, int n_new) {
  AxisWeights axis;
  axis.first.resize(n_new);
  axis.weight.resize(n_new);
  const double step = static_cast<double>(n) / n_new;  // source pixels per target pixel
  for (int i = 0; i < n_new; ++i) {
    const double begin = i * step, end = std::min<double>(n, (i + 1) * step);
    const int first = std::min(n - 1, static_cast<int>(std::floor(begin)));
    axis.first[i] = first;
    double total = 0;
    for (int j = first; j < n && j < end; ++j) {
      const double overlap = std::min<double>(j + 1, end) - std::max<double>(j, begin);
      axis.weight[i].push_back(static_cast<float>(std::max(0.0, overlap)));
      total += std::max(0.0, overlap);
    }
    for (float& w : axis.weight[i]) w = static_cast<float>(w / total);
  }
  return axis;
}

}  // namespace

std::vector<float> ToRgbFloat(const Image& image) {
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  std::vector<float> rgb(3 * pixels);
  for (std::size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = image.pixels[image.channels == 1 ? i : 3 * i + c] / 255.0f;
  return rgb;
}

std::vector<float> Undistort(std::span<const float> rgb, const CameraModel& model,
                             const PinholeIntrinsics& pinhole) {
  const int w = model.width(), h = model.height();
  std::vector<float> out(3 * static_cast<std::size_t>(pinhole.width) * pinhole.height, 0.0f);
  for (int y = 0; y < pinhole.height; ++y) {
    for (int x = 0; x < pinhole.width; ++x) {
      const Eigen::Vector3d ray((x - pinhole.cx) / pinhole.fx, (y - pinhole.cy) / pinhole.fy, 1.0);
      const std::optional<Eigen::Vector2d> p = model.Project(ray);
      if (!p || !model.InImage(*p)) continue;
      // Bilinear between the four pixel centres around p, edge pixels repeated.
      const double u = std::clamp(p->x(), 0.0, w - 1.0), v = std::clamp(p->y(), 0.0, h - 1.0);
      const int x0 = std::min(static_cast<int>(u), w - 1), y0 = std::min(static_cast<int>(v), h - 1);
      const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
      const float fx = static_cast<float>(u - x0), fy = static_cast<float>(v - y0);
      const std::size_t target = 3 * (static_cast<std::size_t>(y) * pinhole.width + x);
      for (int c = 0; c < 3; ++c) {
        auto at = [&](int xi, int yi) { return rgb[3 * (static_cast<std::size_t>(yi) * w + xi) + c]; };
        out[target + c] = (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
                          fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
      }
    }
  }
  return out;
}

std::vector<std::uint8_t> UndistortedCoverage(const CameraModel& model, const PinholeIntrinsics& pinhole) {
  std::vector<std::uint8_t> coverage(static_cast<std::size_t>(pinhole.width) * pinhole.height, 0);
  for (int y = 0; y < pinhole.height; ++y)
    for (int x = 0; x < pinhole.width; ++x) {
      const Eigen::Vector3d ray((x - pinhole.cx) / pinhole.fx, (y - pinhole.cy) / pinhole.fy, 1.0);
      const std::optional<Eigen::Vector2d> p = model.Project(ray);
      coverage[static_cast<std::size_t>(y) * pinhole.width + x] = p && model.InImage(*p) ? 1 : 0;
    }
  return coverage;
}

std::vector<std::uint8_t> ResizeMask(std::span<const std::uint8_t> mask, int width, int height, int new_width,
                                     int new_height) {
  // The share of masked area under each target pixel, by the area weights; any share at all masks it.
  std::vector<float> masked(mask.size());
  for (std::size_t i = 0; i < mask.size(); ++i) masked[i] = mask[i] == 0 ? 1.0f : 0.0f;
  const std::vector<float> share = ResizeArea(masked, width, height, 1, new_width, new_height);
  std::vector<std::uint8_t> out(share.size());
  for (std::size_t i = 0; i < share.size(); ++i) out[i] = share[i] > 1e-4f ? 0 : 1;
  return out;
}

std::vector<float> ResizeArea(std::span<const float> image, int width, int height, int channels,
                              int new_width, int new_height) {
  const AxisWeights wx = BoxWeights(width, new_width), wy = BoxWeights(height, new_height);
  // Separable: rows first (width -> new_width), then columns.
  std::vector<float> rows(static_cast<std::size_t>(height) * new_width * channels, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < new_width; ++x)
      for (std::size_t k = 0; k < wx.weight[x].size(); ++k) {
        const float w = wx.weight[x][k];
        const std::size_t source = (static_cast<std::size_t>(y) * width + wx.first[x] + k) * channels;
        const std::size_t target = (static_cast<std::size_t>(y) * new_width + x) * channels;
        for (int c = 0; c < channels; ++c) rows[target + c] += w * image[source + c];
      }
  std::vector<float> out(static_cast<std::size_t>(new_height) * new_width * channels, 0.0f);
  for (int y = 0; y < new_height; ++y)
    for (std::size_t k = 0; k < wy.weight[y].size(); ++k) {
      const float w = wy.weight[y][k];
      const std::size_t row = static_cast<std::size_t>(wy.first[y]) + k;
      for (int x = 0; x < new_width; ++x)
        for (int c = 0; c < channels; ++c)
          out[(static_cast<std::size_t>(y) * new_width + x) * channels + c] +=
              w * rows[(row * new_width + x) * channels + c];
    }
  return out;
}

PinholeIntrinsics ScalePinhole(const PinholeIntrinsics& p, int width, int height) {
  const double sx = static_cast<double>(width) / p.width, sy = static_cast<double>(height) / p.height;
  PinholeIntrinsics scaled;
  scaled.width = width, scaled.height = height;
  scaled.fx = sx * p.fx, scaled.fy = sy * p.fy;
  scaled.cx = sx * (p.cx + 0.5) - 0.5, scaled.cy = sy * (p.cy + 0.5) - 0.5;
  return scaled;
}

std::vector<float> ResizeDepth(std::span<const float> depth, int width, int height, int new_width,
                               int new_height) {
  const double sx = static_cast<double>(new_width) / width, sy = static_cast<double>(new_height) / height;
  std::vector<float> out(static_cast<std::size_t>(new_width) * new_height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float d = depth[static_cast<std::size_t>(y) * width + x];
      if (d == 0.0f) continue;
      const long tx = std::lround(sx * (x + 0.5) - 0.5), ty = std::lround(sy * (y + 0.5) - 0.5);
      if (tx < 0 || ty < 0 || tx >= new_width || ty >= new_height) continue;
      float& t = out[static_cast<std::size_t>(ty) * new_width + tx];
      if (t == 0.0f || d < t) t = d;
    }
  return out;
}

TrainingView ResizeView(const TrainingView& view, int width, int height) {
  const PinholeIntrinsics& p = view.camera.pinhole;
  TrainingView resized;
  resized.camera = view.camera;
  resized.camera.pinhole = ScalePinhole(p, width, height);
  resized.rgb = ResizeArea(view.rgb, p.width, p.height, 3, width, height);
  if (!view.depth.empty()) resized.depth = ResizeDepth(view.depth, p.width, p.height, width, height);
  if (!view.mask.empty()) resized.mask = ResizeMask(view.mask, p.width, p.height, width, height);
  return resized;
}

std::vector<float> ProjectDepth(std::span<const Eigen::Vector3f> points, const SplatCamera& camera,
                                float near) {
  const PinholeIntrinsics& pinhole = camera.pinhole;
  std::vector<float> depth(static_cast<std::size_t>(pinhole.width) * pinhole.height, 0.0f);
  const SE3 T_camera_world = camera.T_world_camera.inverse();
  const Eigen::Matrix3f R = T_camera_world.rotation().cast<float>();
  const Eigen::Vector3f t = T_camera_world.translation().cast<float>();
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3f c = R * p + t;
    if (!(c.z() > near)) continue;
    const double u = pinhole.fx * c.x() / c.z() + pinhole.cx, v = pinhole.fy * c.y() / c.z() + pinhole.cy;
    const long x = std::lround(u), y = std::lround(v);
    if (x < 0 || y < 0 || x >= pinhole.width || y >= pinhole.height) continue;
    float& d = depth[static_cast<std::size_t>(y) * pinhole.width + x];
    if (d == 0.0f || c.z() < d) d = c.z();
  }
  return depth;
}

}  // namespace uf::splat
