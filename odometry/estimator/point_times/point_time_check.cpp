#include "odometry/estimator/point_times/point_time_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "odometry/estimator/lidar/voxel_downsample.h"
#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/types/printf_text.h"
#include "odometry/types/trajectory.h"

namespace uf::estimator {
namespace {

using Clock = std::chrono::steady_clock;

// The run's settings, LiDAR-only: the LiDAR is the body, no IMU, wheel, GNSS or camera factors; the solver
// stopped by its iteration count only (deterministic).
LidarOdometryConfig LidarOnly(LidarOdometryConfig config) {
  config.use_imu = false;
  config.use_wheel = false;
  config.use_gnss = false;
  config.use_camera = false;
  config.T_body_lidar = SE3();
  config.max_solver_time_s = std::max(config.max_solver_time_s, 10.0);
  return config;
}

Stamp Middle(const LidarScan& scan) { return scan.stamp + (scan.end - scan.stamp) / 2; }

// The pose at t on `trajectory` (>= 1 pose): interpolated between its poses (slerp, lerp), and beyond its
// ends extended with the motion of its first / last interval (the same formula for s outside [0, 1]).
SE3 PoseOn(const Trajectory& trajectory, Stamp t) {
  if (std::optional<SE3> pose = trajectory.PoseAt(t)) return *pose;
  const std::size_t n = trajectory.size();
  if (n == 1) return trajectory.poses.front();
  const std::size_t i = t < trajectory.stamps.front() ? 0 : n - 2;
  const SE3& a = trajectory.poses[i];
  const SE3& b = trajectory.poses[i + 1];
  const double s = static_cast<double>(t - trajectory.stamps[i]) /
                   static_cast<double>(trajectory.stamps[i + 1] - trajectory.stamps[i]);
  return SE3(a.so3() * SO3::Exp(s * (a.so3().inverse() * b.so3()).Log()),
             (1 - s) * a.translation() + s * b.translation());
}

// The scan's points within [min_range, max_range] in the world, each moved by the pose at its own time.
std::vector<Eigen::Vector3f> DeskewAlong(const Trajectory& trajectory, const LidarScan& scan,
                                         double min_range, double max_range) {
  std::vector<Eigen::Vector3f> world;
  world.reserve(scan.points.size());
  for (const LidarPoint& point : scan.points) {
    const Eigen::Vector3d p(point.x, point.y, point.z);
    const double range = p.norm();
    if (!p.allFinite() || range < min_range || range > max_range) continue;
    world.push_back((PoseOn(trajectory, scan.stamp + point.offset_ns) * p).cast<float>());
  }
  return world;
}

// Whether the first `count` scans are keyframes whose sweeps do not touch (the median gap from a sweep's end
// to the next one's start above 1 ms).
bool SeparateSweeps(const std::deque<LidarScan>& scans, std::size_t count) {
  std::vector<Stamp> gaps;
  for (std::size_t i = 1; i < count; ++i) gaps.push_back(scans[i].stamp - scans[i - 1].end);
  if (gaps.empty()) return false;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return gaps[gaps.size() / 2] > 1'000'000;
}

}  // namespace

Status PointTimeCheckOptions::Validate() const {
  auto error = [](const std::string& field, const std::string& rule, double value) {
    return Status::Error("point_time_check." + field + ": must be " + rule + ", got " +
                         PrintfText("%g", value));
  };
  if (min_scans < 2) return error("min_scans", ">= 2", min_scans);
  if (max_scans < min_scans) return error("max_scans", ">= min_scans", max_scans);
  if (max_scans_read < max_scans) return error("max_scans_read", ">= max_scans", max_scans_read);
  if (!(max_still_s > 0)) return error("max_still_s", "> 0", max_still_s);
  if (!(min_sweep_motion_m >= 0)) return error("min_sweep_motion_m", ">= 0", min_sweep_motion_m);
  if (!(reference_range_m > 0)) return error("reference_range_m", "> 0", reference_range_m);
  if (!(margin >= 0 && margin < 1)) return error("margin", "in [0, 1)", margin);
  if (!(thin_voxel_m > 0)) return error("thin_voxel_m", "> 0", thin_voxel_m);
  if (!(max_distance_m > 0)) return error("max_distance_m", "> 0", max_distance_m);
  return {};
}

std::vector<AzimuthConvention> CandidateConventions(const AzimuthConvention& current) {
  if (current.start == SweepStart::kFirstPoint && current.sweep != AzimuthSweep::kNone)
    return {current, Reversed(current), kNoDeskew};
  // A fixed start: both directions from behind and from ahead.
  const AzimuthConvention base = current.sweep == AzimuthSweep::kNone ? kClockwiseFromBehind : current;
  AzimuthConvention other_start = base;
  other_start.start = base.start == SweepStart::kBehind ? SweepStart::kAhead : SweepStart::kBehind;
  std::vector<AzimuthConvention> candidates = {current};
  for (const AzimuthConvention& candidate :
       {base, Reversed(base), other_start, Reversed(other_start), kNoDeskew})
    if (std::find(candidates.begin(), candidates.end(), candidate) == candidates.end())
      candidates.push_back(candidate);
  return candidates;
}

ConventionScore ScoreKeyframes(const std::vector<std::vector<Eigen::Vector3f>>& scans_world,
                               const VoxelMapConfig& map, double max_distance_m) {
  ConventionScore score;
  const std::size_t n = scans_world.size();
  if (n < 3) return score;  // the first is left out: two keyframes at least, one of each parity
  // Keyframe k >= 1 has parity (k - 1) % 2; maps[p] holds the points of parity p.
  VoxelMapConfig scoring = map;
  scoring.max_points_per_voxel = std::max(map.max_points_per_voxel, 100);
  std::vector<VoxelHashMap> maps = {VoxelHashMap(scoring), VoxelHashMap(scoring)};
  for (std::size_t k = 1; k < n; ++k) {
    std::vector<Eigen::Vector3d> points(scans_world[k].size());
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = scans_world[k][i].cast<double>();
    maps[(k - 1) % 2].Insert(points);
  }
  // Per keyframe, then summed in order: the result does not depend on the threads.
  std::vector<double> sums(n, 0.0);
  std::vector<std::int64_t> counts(n, 0);
  tbb::parallel_for(std::size_t{1}, n, [&](std::size_t k) {
    const VoxelHashMap& other = maps[k % 2];  // parity (k - 1) % 2 scored against the other one
    // The plane by voxel: PlaneNear gives every point of a voxel the same one.
    std::unordered_map<std::uint64_t, std::optional<Plane>> planes;
    for (const Eigen::Vector3f& point : scans_world[k]) {
      const Eigen::Vector3d p = point.cast<double>();
      const std::uint64_t key = other.QueryKey(p);
      if (key == VoxelHashMap::kNoQueryKey) continue;
      auto [cached, added] = planes.try_emplace(key);
      if (added) cached->second = other.PlaneNear(p);
      const std::optional<Plane>& plane = cached->second;
      if (!plane) continue;
      sums[k] += std::min(std::abs(plane->normal.dot(p - plane->point)), max_distance_m);
      ++counts[k];
    }
  });
  double sum = 0;
  for (std::size_t k = 1; k < n; ++k) {
    sum += sums[k];
    score.points += counts[k];
  }
  score.keyframes = static_cast<int>(n - 1);
  score.score_m =
      score.points > 0 ? sum / static_cast<double>(score.points) : std::numeric_limits<double>::infinity();
  return score;
}

struct PointTimeCheck::Impl {
  LidarOdometryConfig config;  // LiDAR-only
  AzimuthConvention current;
  PointTimeCheckOptions options;
  LidarOdometry motion;  // over every scan read, with the current convention: the poses that tell motion
  // Thinned scans from the anchor on (before the first motion: from the last still scan on).
  std::deque<LidarScan> held;
  std::map<Stamp, SE3> poses;         // the motion odometry's keyframe poses by keyframe stamp (scan middle)
  std::optional<Stamp> first_moving;  // stamp of the first moving scan
  std::optional<Stamp> first_read, last_read;  // stamps of the first and the latest scan read
  int read = 0;
  double seconds = 0;

  // Whether held[j] moved since held[j - 1]; nullopt while either pose is unknown.
  std::optional<bool> Moved(std::size_t j) const {
    const auto a = poses.find(Middle(held[j - 1])), b = poses.find(Middle(held[j]));
    if (a == poses.end() || b == poses.end()) return std::nullopt;
    const double dt = ToSeconds(b->first - a->first);
    const double period = ToSeconds(held[j].end - held[j].stamp);
    if (!(dt > 0)) return std::nullopt;
    const SE3 delta = a->second.inverse() * b->second;
    const double per_sweep =
        (delta.translation().norm() + delta.so3().angle() * options.reference_range_m) * period / dt;
    return per_sweep >= options.min_sweep_motion_m;
  }

  // Takes the motion odometry's finished keyframes, drops the scans it skipped, and until the first motion
  // drops the still scans but the last one.
  void Update() {
    for (const Keyframe& keyframe : motion.TakeFinished()) poses[keyframe.stamp] = keyframe.T_world_body;
    if (poses.empty()) return;
    const Stamp latest = poses.rbegin()->first;
    std::erase_if(held, [&](const LidarScan& scan) {
      const Stamp middle = Middle(scan);
      return middle < latest && !poses.count(middle);
    });
    // The first motion: held[1] and held[2] both moved (one pose off by noise is not motion).
    while (!first_moving && held.size() >= 3) {
      const std::optional<bool> moved = Moved(1);
      if (!moved) break;
      if (*moved) {
        const std::optional<bool> again = Moved(2);
        if (!again) break;
        if (*again) {
          first_moving = held[1].stamp;
          break;
        }
      }
      held.pop_front();  // held[1] is still (or moved alone): the newest anchor candidate
    }
  }

  int MovingScans(std::size_t count) const {
    int moving = 0;
    for (std::size_t j = 1; j < count; ++j) moving += Moved(j).value_or(false) ? 1 : 0;
    return moving;
  }

  // A LiDAR-only odometry over the first `count` held scans, their times derived by `convention`; then the
  // scans deskewed (step 3: along the trajectory through its keyframe poses, or as its own sweep nodes place
  // them where the sweeps are `separate`), scored.
  Expected<ConventionScore> Score(const AzimuthConvention& convention, std::size_t count,
                                  bool separate) const {
    Expected<LidarOdometry> odometry = LidarOdometry::Create(config);
    if (!odometry) return odometry.status();
    std::vector<LidarScan> scans(held.begin(), held.begin() + static_cast<std::ptrdiff_t>(count));
    for (LidarScan& scan : scans) {
      DeriveAzimuthPointTimes(scan, scan.end - scan.stamp, convention);
      if (Status s = odometry->AddScan(scan); !s.ok()) return s;
    }
    odometry->Finish();
    Trajectory trajectory;
    std::map<Stamp, std::vector<Eigen::Vector3f>> deskewed;  // as the odometry's own sweep nodes place them
    for (Keyframe& keyframe : odometry->TakeFinished()) {
      if (!trajectory.stamps.empty() && keyframe.stamp <= trajectory.stamps.back()) continue;
      trajectory.stamps.push_back(keyframe.stamp);
      trajectory.poses.push_back(keyframe.T_world_body);
      deskewed[keyframe.stamp] = std::move(keyframe.scan_world);
    }
    std::vector<std::vector<Eigen::Vector3f>> scans_world;
    for (const LidarScan& scan : scans) {
      auto own = deskewed.find(Middle(scan));
      if (own == deskewed.end()) continue;
      scans_world.push_back(separate ? std::move(own->second)
                                     : DeskewAlong(trajectory, scan, config.min_range_m, config.max_range_m));
    }
    ConventionScore score = ScoreKeyframes(scans_world, config.map, options.max_distance_m);
    score.convention = convention;
    return score;
  }

  std::string NotCompared(const std::string& why) const {
    return AzimuthConventionText(current) + " kept (the times as read): " + why;
  }

  PointTimeCheckResult Decide();
};

PointTimeCheckResult PointTimeCheck::Impl::Decide() {
  const auto start = Clock::now();
  motion.Finish();
  Update();
  PointTimeCheckResult result;
  result.current = result.chosen = current;
  result.scans_read = read;
  const auto finish = [&]() {
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
    result.seconds = seconds;
    return result;
  };
  const std::string motion_rule = PrintfText("%g", options.min_sweep_motion_m) + " m per sweep at " +
                                  PrintfText("%g", options.reference_range_m) + " m range";
  if (!first_moving) {
    const double span = first_read ? ToSeconds(*last_read - *first_read) : 0.0;
    result.reason = NotCompared("no motion in the " + std::to_string(read) + " scans read over " +
                                PrintfText("%.1f", span) + " s (none moved " + motion_rule +
                                "); every convention fits a still scan equally");
    return finish();
  }
  const std::size_t count = std::min(held.size(), static_cast<std::size_t>(options.max_scans));
  result.scans_used = static_cast<int>(count);
  result.moving_scans = MovingScans(count);
  result.separate_sweeps = SeparateSweeps(held, count);
  if (result.moving_scans < options.min_scans) {
    result.reason =
        NotCompared("only " + std::to_string(result.moving_scans) + " scans moved (" + motion_rule +
                    ") in the " + std::to_string(count) + " scans from the first motion on; " +
                    std::to_string(options.min_scans) + " are needed to compare the conventions");
    return finish();
  }
  for (const AzimuthConvention& candidate : CandidateConventions(current)) {
    Expected<ConventionScore> score = Score(candidate, count, result.separate_sweeps);
    if (!score) {
      result.scores.clear();
      result.reason = NotCompared("the odometry failed: " + score.error());
      return finish();
    }
    result.scores.push_back(*score);
  }
  result.compared = true;
  const ConventionScore& kept = result.scores.front();
  const auto lowest = std::min_element(result.scores.begin(), result.scores.end(),
                                       [](const auto& a, const auto& b) { return a.score_m < b.score_m; });
  // Not `margin` above the lowest score: a tie with it.
  auto ties = [&](const ConventionScore& score) {
    return lowest->score_m >= (1 - options.margin) * score.score_m;
  };
  const bool clearly_better = !ties(kept);
  // The lowest, or a candidate tied with it that spins like the current convention: where the sweeps are
  // separate, the scores do not tell the direction (step 3 in point_time_check.h).
  auto best = lowest;
  if (lowest->convention.sweep != current.sweep)
    for (auto score = result.scores.begin(); score != result.scores.end(); ++score)
      if (score->convention.sweep == current.sweep && ties(*score)) {
        best = score;
        break;
      }
  if (clearly_better) result.chosen = best->convention;
  std::string others;
  for (const ConventionScore& score : result.scores) {
    if (score.convention == result.chosen) continue;
    others += (others.empty() ? " vs " : ", ") + AzimuthConventionText(score.convention) + " " +
              PrintfText("%.4f m", score.score_m);
  }
  const ConventionScore& chosen = clearly_better ? *best : kept;
  result.reason = AzimuthConventionText(result.chosen) + ": point-to-plane " +
                  PrintfText("%.4f m", chosen.score_m) + others + " over " + std::to_string(count) +
                  " scans (" + std::to_string(result.moving_scans) + " moving" +
                  (result.separate_sweeps ? "; separate sweeps, each deskewed by its own nodes)" : ")");
  const std::string within = " is not " + PrintfText("%g", 100 * options.margin) + " % lower";
  if (!clearly_better && lowest->convention != current)
    result.reason += "; kept: " + AzimuthConventionText(lowest->convention) + within;
  else if (clearly_better && best != lowest)
    result.reason += "; the direction kept: " + AzimuthConventionText(lowest->convention) + within;
  return finish();
}

Expected<PointTimeCheck> PointTimeCheck::Create(const LidarOdometryConfig& config,
                                                const AzimuthConvention& current,
                                                const PointTimeCheckOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  const LidarOdometryConfig lidar_only = LidarOnly(config);
  Expected<LidarOdometry> motion = LidarOdometry::Create(lidar_only);
  if (!motion) return motion.status();
  auto impl = std::unique_ptr<Impl>(new Impl{.config = lidar_only,
                                             .current = current,
                                             .options = options,
                                             .motion = std::move(*motion),
                                             .held = {},
                                             .poses = {},
                                             .first_moving = std::nullopt,
                                             .first_read = std::nullopt,
                                             .last_read = std::nullopt});
  return PointTimeCheck(std::move(impl));
}

PointTimeCheck::PointTimeCheck(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
PointTimeCheck::PointTimeCheck(PointTimeCheck&&) noexcept = default;
PointTimeCheck& PointTimeCheck::operator=(PointTimeCheck&&) noexcept = default;
PointTimeCheck::~PointTimeCheck() = default;

Status PointTimeCheck::Add(const LidarScan& scan) {
  if (!scan.point_times_from_azimuth)
    return Status::Error("point time check: a scan whose times were not derived from azimuth");
  const auto start = Clock::now();
  LidarScan thinned = scan;
  thinned.points = VoxelDownsample(scan.points, impl_->options.thin_voxel_m);
  ++impl_->read;
  if (!impl_->first_read) impl_->first_read = scan.stamp;
  impl_->last_read = std::max(impl_->last_read.value_or(scan.stamp), scan.stamp);
  Status status = impl_->motion.AddScan(thinned);
  if (status.ok()) {
    impl_->held.push_back(std::move(thinned));
    impl_->Update();
  }
  impl_->seconds += std::chrono::duration<double>(Clock::now() - start).count();
  return status;
}

bool PointTimeCheck::Done() const {
  const Impl& d = *impl_;
  if (d.read >= d.options.max_scans_read) return true;
  if (d.first_moving) return d.held.size() >= static_cast<std::size_t>(d.options.max_scans);
  return d.first_read && ToSeconds(*d.last_read - *d.first_read) >= d.options.max_still_s;
}

PointTimeCheckResult PointTimeCheck::Decide() { return impl_->Decide(); }

}  // namespace uf::estimator
