#include "odometry/sim/sensors/lidar_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <vector>

#include "odometry/sim/cumulative_spline.h"
#include "odometry/sim/sensors/parallel_for.h"

namespace uf::sim {
namespace {

// Work is split into fixed blocks (independent of the thread count), each with its own RNG seeded from
// (seed, start, block): the output is identical for any number of threads.
constexpr int kColumnsPerBlock = 32;
constexpr std::int64_t kLivoxPointsPerBlock = 1024;

std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

std::uint64_t BlockSeed(std::uint64_t seed, Stamp start, std::uint64_t block) {
  return SplitMix64(SplitMix64(SplitMix64(seed) ^ static_cast<std::uint64_t>(start)) ^ block);
}

template <typename T>
Status FieldError(const char* field, const char* requirement, const T& value) {
  std::ostringstream message;
  message << "lidar." << field << ": " << requirement << ", got " << value;
  return Status::Error(message.str());
}

// floor(a / b) for b > 0 and any sign of a.
std::int64_t FloorDiv(std::int64_t a, std::int64_t b) { return a / b - ((a % b != 0) && (a < 0)); }

// The noise, dropout and intensity of returns, drawn from one block's RNG in acquisition order.
class ReturnModel {
 public:
  ReturnModel(const LidarConfig& config, std::uint64_t seed)
      : config_(config), engine_(seed), noise_(0.0, config.range_noise_std_m) {}

  // The point of a beam with unit direction d (lidar frame; d_world in the world frame) that hit, or false
  // if there is no return (nothing within [min, max] range, or dropped out). The noisy range stays on the
  // beam: p = (distance + noise) d.
  bool Make(const RayHit& hit, const Eigen::Vector3d& d, const Eigen::Vector3f& d_world, LidarPoint& point) {
    if (!hit.hit() || hit.distance < config_.min_range_m || hit.distance > config_.max_range_m) return false;
    if (config_.dropout_probability > 0.0 && uniform_(engine_) < config_.dropout_probability) return false;
    double range = hit.distance;
    if (config_.range_noise_std_m > 0.0) range += noise_(engine_);
    point.x = static_cast<float>(range * d.x());
    point.y = static_cast<float>(range * d.y());
    point.z = static_cast<float>(range * d.z());
    // Lambertian return: I = 255 rho |cos(theta)|, theta between beam and normal (both unit, world frame).
    const double cos_incidence = std::abs(static_cast<double>(hit.normal.dot(d_world)));
    const double reflectivity = AppearanceOf(hit.material).reflectivity;
    point.intensity =
        static_cast<float>(std::round(std::clamp(255.0 * reflectivity * cos_incidence, 0.0, 255.0)));
    return true;
  }

 private:
  const LidarConfig& config_;
  std::mt19937_64 engine_;
  std::normal_distribution<double> noise_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// TrajectorySpline::Pose with the per-segment part cached: the rotation increments d_j = Log(R_{j-1}^T R_j)
// and position steps c_j - c_{j-1} are computed once per segment, so consecutive firings (thousands per
// segment) pay only R(u) = R_0 prod_j Exp(lambda_j(u) d_j) and p(u) = c_0 + sum_j lambda_j(u) (c_j - c_{j-1})
// (cumulative_spline.h). Same operations in the same order as TrajectorySpline::Pose. One per thread.
class CachedSplinePoser {
 public:
  explicit CachedSplinePoser(const TrajectorySpline& spline) : spline_(spline) {}

  SE3 Pose(Stamp t) {
    const spline::SegmentCoordinate where =
        spline::LocateSegment(t, spline_.begin(), spline_.knot_spacing(), spline_.segments());
    if (where.index != segment_) Load(where.index);
    const Eigen::Vector4d lambda = spline::CumulativeBasisAt(where.u).value;
    Eigen::Vector3d position = origin_.translation();
    SO3 rotation = origin_.so3();
    for (int j = 1; j < 4; ++j) {
      position += lambda(j) * steps_[j];
      rotation = rotation * SO3::Exp(lambda(j) * increments_[j]);
    }
    return SE3(rotation, position);
  }

 private:
  void Load(int segment) {
    const std::vector<SE3>& controls = spline_.control_points();
    segment_ = segment;
    origin_ = controls[segment];
    for (int j = 1; j < 4; ++j) {
      const SE3& previous = controls[segment + j - 1];
      const SE3& current = controls[segment + j];
      steps_[j] = current.translation() - previous.translation();
      increments_[j] = (previous.so3().inverse() * current.so3()).Log();
    }
  }

  const TrajectorySpline& spline_;
  int segment_ = -1;
  SE3 origin_;
  std::array<Eigen::Vector3d, 4> steps_, increments_;  // index 1..3
};

// The sweep [start, start + period] with the points of every block in block order.
LidarScan AssembleScan(Stamp start, Stamp period, const std::vector<std::vector<LidarPoint>>& blocks) {
  LidarScan scan;
  scan.stamp = start;
  scan.end = start + period;
  scan.has_point_times = true;
  scan.has_ring = true;
  std::size_t total = 0;
  for (const auto& block : blocks) total += block.size();
  scan.points.reserve(total);
  for (const auto& block : blocks) scan.points.insert(scan.points.end(), block.begin(), block.end());
  return scan;
}

}  // namespace

Status ValidateLidarConfig(const LidarConfig& c) {
  if (!IsKnownLidarModel(c.model)) {
    return FieldError("model", "must be spinning16, spinning32, spinning64, spinning128 or livox_avia",
                      "'" + c.model + "'");
  }
  // At least 0.5 Hz: a period beyond 2.147 s would overflow LidarPoint::offset_ns (int32 ns).
  if (!(c.rate_hz >= 0.5 && c.rate_hz <= 100.0)) {
    return FieldError("rate_hz", "must be in [0.5, 100]", c.rate_hz);
  }
  if (!(c.horizontal_resolution_deg > 0.0 && c.horizontal_resolution_deg <= 10.0)) {
    return FieldError("horizontal_resolution_deg", "must be in (0, 10]", c.horizontal_resolution_deg);
  }
  if (!(c.min_range_m >= 0.0 && c.min_range_m < 10000.0)) {
    return FieldError("min_range_m", "must be in [0, 10000)", c.min_range_m);
  }
  if (!(c.max_range_m > c.min_range_m && c.max_range_m <= 10000.0)) {
    return FieldError("max_range_m", "must be in (min_range_m, 10000]", c.max_range_m);
  }
  if (!(c.range_noise_std_m >= 0.0 && c.range_noise_std_m <= 10.0)) {
    return FieldError("range_noise_std_m", "must be in [0, 10]", c.range_noise_std_m);
  }
  if (!(c.dropout_probability >= 0.0 && c.dropout_probability <= 1.0)) {
    return FieldError("dropout_probability", "must be in [0, 1]", c.dropout_probability);
  }
  if (c.threads < 0) return FieldError("threads", "must be >= 0 (0: all cores)", c.threads);
  return Status();
}

Expected<LidarSimulator> LidarSimulator::Create(const LidarConfig& config, const RayCaster& caster,
                                                const TrajectorySpline& spline, const SE3& T_body_lidar,
                                                std::uint64_t seed) {
  if (Status status = ValidateLidarConfig(config); !status.ok()) return status;
  LidarSimulator simulator;
  simulator.config_ = config;
  simulator.caster_ = &caster;
  simulator.spline_ = &spline;
  simulator.T_body_lidar_ = T_body_lidar;
  simulator.seed_ = seed;
  simulator.period_ = static_cast<Stamp>(std::llround(1e9 / config.rate_hz));
  if (std::optional<SpinningPattern> pattern = SpinningPatternFor(config.model)) {
    simulator.elevations_rad_ = std::move(pattern->elevations_rad);
    simulator.columns_ = static_cast<int>(std::lround(360.0 / config.horizontal_resolution_deg));
  }
  return simulator;
}

int LidarSimulator::rings() const {
  return is_spinning() ? static_cast<int>(elevations_rad_.size()) : kLivoxHeads;
}

Expected<LidarScan> LidarSimulator::Scan(Stamp start) const {
  if (!spline_->Contains(start) || !spline_->Contains(start + period_)) {
    std::ostringstream message;
    message << "lidar scan [" << start << ", " << start + period_ << "] ns is outside the trajectory ["
            << spline_->begin() << ", " << spline_->end() << "] ns";
    return Status::Error(message.str());
  }
  return is_spinning() ? ScanSpinning(start) : ScanLivox(start);
}

Expected<LidarScan> LidarSimulator::ScanSpinning(Stamp start) const {
  const int beams = rings();
  // Beam b of column c, lidar frame: (cos e_b cos a_c, cos e_b sin a_c, sin e_b), a_c = pi - 2 pi c /
  // columns.
  std::vector<double> cos_elevation(beams), sin_elevation(beams);
  for (int b = 0; b < beams; ++b) {
    cos_elevation[b] = std::cos(elevations_rad_[b]);
    sin_elevation[b] = std::sin(elevations_rad_[b]);
  }
  const float max_range = static_cast<float>(config_.max_range_m);
  const std::size_t blocks = (columns_ + kColumnsPerBlock - 1) / kColumnsPerBlock;
  std::vector<std::vector<LidarPoint>> block_points(blocks);
  ParallelFor(blocks, config_.threads, [&](std::size_t block_begin, std::size_t block_end) {
    std::vector<Ray> rays;
    std::vector<RayHit> hits;
    std::vector<Eigen::Vector3d> directions;  // lidar frame
    CachedSplinePoser poser(*spline_);
    for (std::size_t block = block_begin; block < block_end; ++block) {
      const int first = static_cast<int>(block) * kColumnsPerBlock;
      const int last = std::min(columns_, first + kColumnsPerBlock);
      const std::size_t count = static_cast<std::size_t>(last - first) * beams;
      rays.resize(count);
      hits.resize(count);
      directions.resize(count);
      std::vector<std::int32_t> offsets(last - first);
      for (int c = first; c < last; ++c) {
        // One firing time per column; the pose at that time (rolling acquisition), once per column.
        const Stamp offset = static_cast<Stamp>(c) * period_ / columns_;
        offsets[c - first] = static_cast<std::int32_t>(offset);
        const SE3 T_world_lidar = poser.Pose(start + offset) * T_body_lidar_;
        const Eigen::Matrix3d& R = T_world_lidar.rotation();
        const Eigen::Vector3f origin = T_world_lidar.translation().cast<float>();
        const double azimuth = std::numbers::pi - 2.0 * std::numbers::pi * c / columns_;
        const double cos_azimuth = std::cos(azimuth), sin_azimuth = std::sin(azimuth);
        for (int b = 0; b < beams; ++b) {
          const std::size_t i = static_cast<std::size_t>(c - first) * beams + b;
          directions[i] = Eigen::Vector3d(cos_elevation[b] * cos_azimuth, cos_elevation[b] * sin_azimuth,
                                          sin_elevation[b]);
          rays[i].origin = origin;
          rays[i].direction = (R * directions[i]).cast<float>();
          rays[i].max_range = max_range;
        }
      }
      caster_->Cast(rays, hits);
      ReturnModel model(config_, BlockSeed(seed_, start, block));
      std::vector<LidarPoint>& points = block_points[block];
      points.reserve(count);
      for (std::size_t i = 0; i < count; ++i) {
        LidarPoint point;
        if (!model.Make(hits[i], directions[i], rays[i].direction, point)) continue;
        point.ring = static_cast<std::uint16_t>(i % beams);
        point.offset_ns = offsets[i / beams];
        points.push_back(point);
      }
    }
  });
  return AssembleScan(start, period_, block_points);
}

Expected<LidarScan> LidarSimulator::ScanLivox(Stamp start) const {
  // Points n with start <= n * interval < start + period.
  const std::int64_t first = FloorDiv(start - 1, kLivoxPointIntervalNs) + 1;
  const std::int64_t end = FloorDiv(start + period_ - 1, kLivoxPointIntervalNs) + 1;
  const std::int64_t count = std::max<std::int64_t>(0, end - first);
  const std::size_t blocks =
      static_cast<std::size_t>((count + kLivoxPointsPerBlock - 1) / kLivoxPointsPerBlock);
  const float max_range = static_cast<float>(config_.max_range_m);
  std::vector<std::vector<LidarPoint>> block_points(blocks);
  ParallelFor(blocks, config_.threads, [&](std::size_t block_begin, std::size_t block_end) {
    std::vector<Ray> rays;
    std::vector<RayHit> hits;
    std::vector<Eigen::Vector3d> directions;
    CachedSplinePoser poser(*spline_);
    for (std::size_t block = block_begin; block < block_end; ++block) {
      const std::int64_t block_first = first + static_cast<std::int64_t>(block) * kLivoxPointsPerBlock;
      const std::int64_t block_end_n = std::min(end, block_first + kLivoxPointsPerBlock);
      const std::size_t size = static_cast<std::size_t>(block_end_n - block_first);
      rays.resize(size);
      hits.resize(size);
      directions.resize(size);
      for (std::size_t i = 0; i < size; ++i) {
        // Continuous per-point times: every point has its own pose.
        const std::int64_t n = block_first + static_cast<std::int64_t>(i);
        const SE3 T_world_lidar = poser.Pose(n * kLivoxPointIntervalNs) * T_body_lidar_;
        directions[i] = LivoxDirection(n);
        rays[i].origin = T_world_lidar.translation().cast<float>();
        rays[i].direction = (T_world_lidar.rotation() * directions[i]).cast<float>();
        rays[i].max_range = max_range;
      }
      caster_->Cast(rays, hits);
      ReturnModel model(config_, BlockSeed(seed_, start, block));
      std::vector<LidarPoint>& points = block_points[block];
      points.reserve(size);
      for (std::size_t i = 0; i < size; ++i) {
        LidarPoint point;
        if (!model.Make(hits[i], directions[i], rays[i].direction, point)) continue;
        const std::int64_t n = block_first + static_cast<std::int64_t>(i);
        point.ring = static_cast<std::uint16_t>(((n % kLivoxHeads) + kLivoxHeads) % kLivoxHeads);
        point.offset_ns = static_cast<std::int32_t>(n * kLivoxPointIntervalNs - start);
        points.push_back(point);
      }
    }
  });
  return AssembleScan(start, period_, block_points);
}

}  // namespace uf::sim
