#include "splat/views/distorted_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uf::splat {

DistortedViewResampler::DistortedViewResampler(const CameraModel& model,
                                               const PinholeIntrinsics& model_pinhole, double max_scale)
    : width_(model.width()), height_(model.height()) {
  const double fx = model_pinhole.fx, fy = model_pinhole.fy, cx0 = model_pinhole.cx, cy0 = model_pinhole.cy;
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  u_.assign(n, std::numeric_limits<float>::quiet_NaN());
  v_.assign(n, std::numeric_limits<float>::quiet_NaN());
  // Normalized pinhole coordinates (x/z, y/z) of every pixel's ray and their extent.
  std::vector<double> xs(n), ys(n);
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Eigen::Vector3d b = model.Unproject(Eigen::Vector2d(x, y));
      const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
      if (!(b.z() > 1e-6) || !b.allFinite()) {
        xs[i] = ys[i] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      xs[i] = b.x() / b.z();
      ys[i] = b.y() / b.z();
      x_min = std::min(x_min, xs[i]), x_max = std::max(x_max, xs[i]);
      y_min = std::min(y_min, ys[i]), y_max = std::max(y_max, ys[i]);
    }
  // Extent of the rays in a pinhole image with the model's principal point, capped at max_scale, then a
  // whole-pixel shift of the principal point (no resampling blur without distortion) and a one-pixel margin
  // for the bilinear footprint.
  const double half_w = max_scale * width_ / 2.0, half_h = max_scale * height_ / 2.0;
  const double u_lo = std::max(fx * x_min, -half_w) + cx0, u_hi = std::min(fx * x_max, half_w) + cx0;
  const double v_lo = std::max(fy * y_min, -half_h) + cy0, v_hi = std::min(fy * y_max, half_h) + cy0;
  const double shift_u = std::ceil(-u_lo) + 1.0, shift_v = std::ceil(-v_lo) + 1.0;
  PinholeIntrinsics& pinhole = pinhole_.pinhole;
  pinhole.fx = fx;
  pinhole.fy = fy;
  pinhole.cx = cx0 + shift_u;
  pinhole.cy = cy0 + shift_v;
  pinhole.width = static_cast<int>(std::floor(u_hi + shift_u)) + 2;
  pinhole.height = static_cast<int>(std::floor(v_hi + shift_v)) + 2;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(xs[i])) continue;
    const double u = fx * xs[i] + pinhole.cx, v = fy * ys[i] + pinhole.cy;
    if (u < 0 || v < 0 || u > pinhole.width - 1 || v > pinhole.height - 1) continue;
    u_[i] = static_cast<float>(u);
    v_[i] = static_cast<float>(v);
  }
}

SplatCamera DistortedViewResampler::Pinhole(const SE3& T_world_camera) const {
  SplatCamera camera = pinhole_;
  camera.T_world_camera = T_world_camera;
  return camera;
}

RenderedView DistortedViewResampler::Resample(const RenderedView& pinhole,
                                              const Eigen::Vector3f& background) const {
  RenderedView view = RenderedView::Sized(width_, height_);
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  const int w = pinhole.width;
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) view.rgb[3 * i + c] = background[c];
    if (std::isnan(u_[i])) continue;
    // Bilinear weights of the four pinhole pixels around (u, v); u, v lie inside [0, w - 1] x [0, h - 1].
    const int x0 = std::min(static_cast<int>(u_[i]), std::max(w - 2, 0));
    const int y0 = std::min(static_cast<int>(v_[i]), std::max(pinhole.height - 2, 0));
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, pinhole.height - 1);
    const float fu = u_[i] - x0, fv = v_[i] - y0;
    const std::size_t p[4] = {static_cast<std::size_t>(y0) * w + x0, static_cast<std::size_t>(y0) * w + x1,
                              static_cast<std::size_t>(y1) * w + x0, static_cast<std::size_t>(y1) * w + x1};
    const float weight[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
    for (int c = 0; c < 3; ++c) {
      float value = 0;
      for (int k = 0; k < 4; ++k) value += weight[k] * pinhole.rgb[3 * p[k] + c];
      view.rgb[3 * i + c] = value;
    }
    float alpha = 0;
    for (int k = 0; k < 4; ++k) alpha += weight[k] * pinhole.alpha[p[k]];
    view.alpha[i] = alpha;
    const std::size_t nearest = static_cast<std::size_t>(std::lround(v_[i])) * w + std::lround(u_[i]);
    view.depth[i] = pinhole.depth[nearest];
    view.expected_depth[i] = pinhole.expected_depth[nearest];
  }
  return view;
}

}  // namespace uf::splat
