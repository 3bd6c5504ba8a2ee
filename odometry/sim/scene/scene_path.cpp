#include "odometry/sim/scene/scene_path.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace uf::sim {

namespace {

// Distance from point p to segment [a, b] in 2D; t = clamp((p - a).(b - a) / |b - a|^2, 0, 1).
double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                            double* t_out = nullptr) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  if (t_out != nullptr) *t_out = t;
  return (a + t * ab - p).norm();
}

double Cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Proper or touching intersection of segments [a, b] and [c, d] (orientation tests).
bool SegmentsIntersect(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                       const Eigen::Vector2d& d) {
  const double d1 = Cross2(b - a, c - a), d2 = Cross2(b - a, d - a);
  const double d3 = Cross2(d - c, a - c), d4 = Cross2(d - c, b - c);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

// Inside a counter-clockwise convex polygon: left of (or on) every edge.
bool InsideConvex(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  for (std::size_t i = 0; i < poly.size(); ++i) {
    if (Cross2(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]) < 0.0) return false;
  }
  return true;
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

}  // namespace

ScenePath::ScenePath(std::vector<Sample> samples, double spacing, double body_height)
    : samples_(std::move(samples)), spacing_(spacing), body_height_(body_height) {
  BuildIndex();
}

Expected<ScenePath> ScenePath::FromTrajectory(const Trajectory& poses, double spacing_m,
                                              double body_height_m) {
  if (poses.size() < 2) {
    return Status::Error("scene path: trajectory needs at least 2 poses, got " +
                         std::to_string(poses.size()));
  }
  if (!(spacing_m > 0.0))
    return Status::Error("scene path: spacing_m must be > 0, got " + std::to_string(spacing_m));
  if (!(body_height_m >= 0.0)) {
    return Status::Error("scene path: body_height_m must be >= 0, got " + std::to_string(body_height_m));
  }
  std::vector<Eigen::Vector3d> p;
  p.reserve(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d& t = poses.poses[i].translation();
    if (!t.allFinite()) return Status::Error("scene path: pose " + std::to_string(i) + " is not finite");
    p.push_back(t);
  }
  // Cumulative xy arc length c_i of the input positions.
  std::vector<double> c(p.size(), 0.0);
  for (std::size_t i = 1; i < p.size(); ++i) c[i] = c[i - 1] + (p[i] - p[i - 1]).head<2>().norm();
  const double total = c.back();
  std::vector<Sample> samples;
  if (total < 1e-3) {
    // Not moving: a 1 mm track along the first pose's x axis.
    const Eigen::Vector3d x = poses.poses.front().rotation().col(0);
    const double heading = std::atan2(x.y(), x.x());
    const Eigen::Vector3d dir(std::cos(heading), std::sin(heading), 0.0);
    samples.push_back({p.front(), heading, 0.0});
    samples.push_back({p.front() + 1e-3 * dir, heading, 1e-3});
    return ScenePath(std::move(samples), spacing_m, body_height_m);
  }
  const int n = std::max(1, static_cast<int>(std::ceil(total / spacing_m)));
  const double step = total / n;
  for (int k = 0; k <= n; ++k) {
    const double s = std::min(k * step, total);
    // First input segment whose end reaches s (skips zero-length segments of standstill).
    std::size_t i = static_cast<std::size_t>(std::lower_bound(c.begin() + 1, c.end(), s) - c.begin());
    i = std::min(i, p.size() - 1);
    const double len = c[i] - c[i - 1];
    const double t = len > 0.0 ? std::clamp((s - c[i - 1]) / len, 0.0, 1.0) : 1.0;
    samples.push_back({p[i - 1] + t * (p[i] - p[i - 1]), 0.0, s});
  }
  // Headings from central differences of the resampled track.
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const std::size_t a = k > 0 ? k - 1 : 0, b = std::min(k + 1, samples.size() - 1);
    const Eigen::Vector3d d = samples[b].position - samples[a].position;
    samples[k].heading = std::atan2(d.y(), d.x());
  }
  return ScenePath(std::move(samples), step, body_height_m);
}

ScenePath ScenePath::Extended(double meters) const {
  assert(meters >= 0.0);
  const int extra = static_cast<int>(std::ceil(meters / spacing_));
  const double step = extra > 0 ? meters / extra : 0.0;
  std::vector<Sample> out;
  out.reserve(samples_.size() + 2 * extra);
  const Sample& first = samples_.front();
  const Sample& last = samples_.back();
  const Eigen::Vector3d d0(std::cos(first.heading), std::sin(first.heading), 0.0);
  const Eigen::Vector3d d1(std::cos(last.heading), std::sin(last.heading), 0.0);
  for (int k = extra; k >= 1; --k) out.push_back({first.position - k * step * d0, first.heading, 0.0});
  for (const Sample& s : samples_) out.push_back(s);
  for (int k = 1; k <= extra; ++k) out.push_back({last.position + k * step * d1, last.heading, 0.0});
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (k < static_cast<std::size_t>(extra)) {
      out[k].s = (static_cast<double>(k)) * step;
    } else if (k < static_cast<std::size_t>(extra) + samples_.size()) {
      out[k].s = samples_[k - extra].s - first.s + meters;
    } else {
      out[k].s = out[k - 1].s + step;
    }
  }
  return ScenePath(std::move(out), spacing_, body_height_);
}

void ScenePath::BuildIndex() {
  min_xy_ = max_xy_ = samples_.front().position.head<2>();
  for (const Sample& s : samples_) {
    min_xy_ = min_xy_.cwiseMin(s.position.head<2>());
    max_xy_ = max_xy_.cwiseMax(s.position.head<2>());
  }
  const Eigen::Vector2d extent = max_xy_ - min_xy_;
  cell_ = std::max({8.0, 4.0 * spacing_, extent.maxCoeff() / 256.0});
  grid_nx_ = static_cast<int>(extent.x() / cell_) + 1;
  grid_ny_ = static_cast<int>(extent.y() / cell_) + 1;
  grid_.assign(static_cast<std::size_t>(grid_nx_) * grid_ny_, {});
  for (std::size_t i = 0; i + 1 < samples_.size(); ++i) {
    const Eigen::Vector2d a = samples_[i].position.head<2>(), b = samples_[i + 1].position.head<2>();
    {
      const int seg_index = static_cast<int>(i);
      const Eigen::Vector2d lo = a.cwiseMin(b) - min_xy_, hi = a.cwiseMax(b) - min_xy_;
      const int ix0 = std::clamp(static_cast<int>(lo.x() / cell_), 0, grid_nx_ - 1);
      const int ix1 = std::clamp(static_cast<int>(hi.x() / cell_), 0, grid_nx_ - 1);
      const int iy0 = std::clamp(static_cast<int>(lo.y() / cell_), 0, grid_ny_ - 1);
      const int iy1 = std::clamp(static_cast<int>(hi.y() / cell_), 0, grid_ny_ - 1);
      for (int iy = iy0; iy <= iy1; ++iy) {
        for (int ix = ix0; ix <= ix1; ++ix) grid_[iy * grid_nx_ + ix].push_back(seg_index);
      }
    }
  }
}

ScenePath::Nearest ScenePath::NearestPoint(double x, double y) const {
  const Eigen::Vector2d q(x, y);
  Nearest best;
  best.distance = std::numeric_limits<double>::infinity();
  const int qx = std::clamp(static_cast<int>(std::floor((x - min_xy_.x()) / cell_)), 0, grid_nx_ - 1);
  const int qy = std::clamp(static_cast<int>(std::floor((y - min_xy_.y()) / cell_)), 0, grid_ny_ - 1);
  auto visit = [&](int ix, int iy) {
    if (ix < 0 || iy < 0 || ix >= grid_nx_ || iy >= grid_ny_) return;
    for (int i : grid_[iy * grid_nx_ + ix]) {
      const Eigen::Vector2d a = samples_[i].position.head<2>(), b = samples_[i + 1].position.head<2>();
      double t = 0.0;
      const double d = PointSegmentDistance(q, a, b, &t);
      if (d < best.distance) {
        best.distance = d;
        best.s = samples_[i].s + t * (samples_[i + 1].s - samples_[i].s);
        best.z = samples_[i].position.z() + t * (samples_[i + 1].position.z() - samples_[i].position.z());
        best.lateral = Cross2(b - a, q - a) >= 0.0 ? d : -d;
      }
    }
  };
  // Rings of cells around the query's (clamped) cell: every segment outside ring r is at least r * cell
  // away, so stop once the best distance is within that bound.
  const int max_ring = std::max(grid_nx_, grid_ny_);
  for (int r = 0; r <= max_ring; ++r) {
    for (int ix = qx - r; ix <= qx + r; ++ix) {
      visit(ix, qy - r);
      if (r > 0) visit(ix, qy + r);
    }
    for (int iy = qy - r + 1; iy <= qy + r - 1; ++iy) {
      visit(qx - r, iy);
      visit(qx + r, iy);
    }
    if (best.distance <= r * cell_) break;
  }
  return best;
}

ScenePath::Sample ScenePath::At(double s) const {
  if (s <= samples_.front().s) return samples_.front();
  if (s >= samples_.back().s) return samples_.back();
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), s,
                                   [](double value, const Sample& sample) { return value < sample.s; });
  const Sample& b = *it;
  const Sample& a = *(it - 1);
  const double t = b.s > a.s ? (s - a.s) / (b.s - a.s) : 0.0;
  return {a.position + t * (b.position - a.position), a.heading + t * WrapAngle(b.heading - a.heading), s};
}

std::vector<Eigen::Vector3d> ScenePath::GroundPolyline(double s0, double s1, double z_offset) const {
  const Eigen::Vector3d dz(0.0, 0.0, z_offset - body_height_);
  std::vector<Eigen::Vector3d> out;
  out.push_back(At(s0).position + dz);
  for (const Sample& sample : samples_) {
    if (sample.s > s0 + 1e-6 && sample.s < s1 - 1e-6) out.push_back(sample.position + dz);
  }
  out.push_back(At(s1).position + dz);
  return out;
}

Eigen::Vector3d ScenePath::GroundPoint(double s, double lateral, double up) const {
  const Sample sample = At(s);
  const Eigen::Vector3d left(-std::sin(sample.heading), std::cos(sample.heading), 0.0);
  return sample.position + lateral * left + Eigen::Vector3d(0.0, 0.0, up - body_height_);
}

std::vector<int> ScenePath::SegmentsNear(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const {
  std::vector<int> out;
  if ((hi.array() < min_xy_.array()).any() || (lo.array() > (max_xy_.array() + cell_)).any()) return out;
  const int ix0 = std::clamp(static_cast<int>(std::floor((lo.x() - min_xy_.x()) / cell_)), 0, grid_nx_ - 1);
  const int ix1 = std::clamp(static_cast<int>(std::floor((hi.x() - min_xy_.x()) / cell_)), 0, grid_nx_ - 1);
  const int iy0 = std::clamp(static_cast<int>(std::floor((lo.y() - min_xy_.y()) / cell_)), 0, grid_ny_ - 1);
  const int iy1 = std::clamp(static_cast<int>(std::floor((hi.y() - min_xy_.y()) / cell_)), 0, grid_ny_ - 1);
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) {
      const auto& cell = grid_[iy * grid_nx_ + ix];
      out.insert(out.end(), cell.begin(), cell.end());
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool ScenePath::PolygonClear(const std::vector<Eigen::Vector2d>& polygon, double clearance) const {
  assert(polygon.size() >= 3);
  Eigen::Vector2d lo = polygon.front(), hi = polygon.front();
  for (const auto& v : polygon) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector2d margin = Eigen::Vector2d::Constant(clearance);
  for (int i : SegmentsNear(lo - margin, hi + margin)) {
    const Eigen::Vector2d a = samples_[i].position.head<2>(), b = samples_[i + 1].position.head<2>();
    if (InsideConvex(a, polygon) || InsideConvex(b, polygon)) return false;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const Eigen::Vector2d& c = polygon[k];
      const Eigen::Vector2d& d = polygon[(k + 1) % polygon.size()];
      if (SegmentsIntersect(a, b, c, d)) return false;
      // Non-intersecting segments: their distance is attained at an endpoint of one of them.
      const double dist = std::min({PointSegmentDistance(a, c, d), PointSegmentDistance(b, c, d),
                                    PointSegmentDistance(c, a, b), PointSegmentDistance(d, a, b)});
      if (dist < clearance) return false;
    }
  }
  return true;
}

}  // namespace uf::sim
