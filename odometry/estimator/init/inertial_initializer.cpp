#include "odometry/estimator/init/inertial_initializer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include "odometry/estimator/init/short_window_map.h"

namespace uf::estimator {
namespace {

std::string Vector(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(3);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

}  // namespace

std::string InitializationRecord::Summary() const {
  if (!admitted) return "";
  std::ostringstream out;
  out.precision(4);
  out << InitModeLetter(mode) << " (" << InitModeName(mode) << ") after " << latency_s << " s, at "
      << StampText(admitted_at) << ", " << scans << " scans: gravity " << gravity_estimate
      << " m/s^2, in the imu frame " << Vector(gravity_imu);
  if (mode == InitMode::kLidarAided)
    out << ", direction sigma " << tilt_sigma_deg << " deg (LO noise " << lidar_sigma_m << " m)";
  out << ", velocity " << Vector(velocity) << " m/s, accel bias " << Vector(accel_bias)
      << " m/s^2, gyro bias " << Vector(gyro_bias) << " rad/s, check chi2 " << chi2_per_dof << " per dof; "
      << attempts << (attempts == 1 ? " attempt" : " attempts") << " (" << deferred << " deferred, "
      << rejected << " rejected)";
  for (const std::string& rejection : rejections) out << "; rejected " << rejection;
  if (initializations > 1) out << "; initialization " << initializations << " of the run";
  return out.str();
}

InertialInitializer::InertialInitializer(const InertialInitConfig& config, const ImuNoiseParams& imu,
                                         double imu_max_gap_s)
    : config_(config), imu_params_(imu), imu_max_gap_s_(imu_max_gap_s), imu_(imu, imu_max_gap_s) {}

void InertialInitializer::Start(Stamp first_imu) {
  const int initializations = record_.initializations;
  record_ = InitializationRecord{};
  record_.initializations = initializations;
  record_.first_imu = first_imu;
  started_ = true;
  scans_.clear();
  imu_ = ImuBuffer(imu_params_, imu_max_gap_s_);
  last_window_id_ = -1;
  first_allowed_id_ = std::numeric_limits<long>::min();
  settled_id_ = std::numeric_limits<long>::max();
  map_scans_ = 0;
  previous_gravity_.reset();
}

// Takes the odometry window's scans (new ones appended, those still in it updated to their current poses,
// those that left it kept as they last were) and the IMU samples not copied yet; at most max_scans scans.
void InertialInitializer::Update(const ImuBuffer& imu, const InitWindow& window) {
  const long first_id = window.scans.front().id;
  if (last_window_id_ < 0 || first_id > last_window_id_) {  // the first attempt, or the local map restarted
    scans_.clear();
    map_scans_ = 0;
    settled_id_ = std::numeric_limits<long>::max();
  }
  for (const InitScan& scan : window.scans)
    if (scan.id > last_window_id_ && map_scans_++ == config_.map_settle_scans) settled_id_ = scan.id;
  last_window_id_ = window.scans.back().id;
  while (!scans_.empty() && scans_.back().id >= first_id) scans_.pop_back();
  for (const InitScan& scan : window.scans)
    if (scan.id >= first_allowed_id_) scans_.push_back(scan);
  while (static_cast<int>(scans_.size()) > config_.max_scans) scans_.pop_front();
  const Stamp covered = imu_.CoveredUntil();
  for (const ImuSample& sample :
       imu.Between(imu_.empty() ? scans_.front().begin : covered + 1, std::numeric_limits<Stamp>::max()))
    imu_.Add(sample);  // already screened by the window's buffer
  imu_.Trim(scans_.front().begin);
}

// The velocity of each odometry window node from the initialization window's first begin on, from those at
// the scans' middles (`middles`, `poses`: those the mode used, a.velocities at them; see the header); a node
// whose interval the IMU does not cover takes its middle's.
std::vector<Eigen::Vector3d> InertialInitializer::NodeVelocities(const InertialAlignment& a,
                                                                 std::span<const Stamp> middles,
                                                                 std::span<const SE3> poses,
                                                                 const InitWindow& window) const {
  const Eigen::Vector3d g(0, 0, -imu_params_.gravity);
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < window.node_stamps.size(); ++i) {
    const Stamp t = window.node_stamps[i];
    if (t < scans_.front().begin) continue;
    std::size_t m = 0;
    while (m + 1 < middles.size() && middles[m + 1] <= t) ++m;
    const Stamp t_m = middles[m];
    const Eigen::Vector3d& v_m = a.velocities[m];
    const bool after = t_m <= t;
    Expected<ImuPreintegration> pre =
        t == t_m ? Status::Error("same stamp")
                 : imu_.Preintegrate(after ? t_m : t, after ? t : t_m, a.accel_bias, a.gyro_bias);
    if (!pre) {
      out.push_back(v_m);
      continue;
    }
    const SO3 R_from = a.R_gravity_lo * (after ? poses[m] : window.node_poses[i]).so3();
    const Eigen::Vector3d dv = g * pre->sum_dt_seconds() + R_from * pre->delta_v();
    out.push_back(after ? Eigen::Vector3d(v_m + dv) : Eigen::Vector3d(v_m - dv));
  }
  return out;
}

InertialInitializer::Outcome InertialInitializer::Attempt(const ImuBuffer& imu, const InitWindow& window) {
  using Verdict = AdmissionCheck::Verdict;
  Outcome out;
  ++record_.attempts;
  Update(imu, window);
  const double gravity = imu_params_.gravity;
  const Stamp now = window.node_stamps.back();
  // S uses every scan (their poses only for E_v), M the registered ones past the map's first
  // map_settle_scans.
  std::vector<Stamp> stamps, lidar_stamps;
  std::vector<SE3> poses, lidar_poses;
  for (const InitScan& scan : scans_) {
    stamps.push_back(scan.middle);
    poses.push_back(scan.pose);
    if (scan.registered && scan.id >= settled_id_) {
      lidar_stamps.push_back(scan.middle);
      lidar_poses.push_back(scan.pose);
    }
  }
  InitIndicators indicators = ComputeInitIndicators(imu_.Between(scans_.front().begin, now), stamps, poses,
                                                    config_.lidar_position_sigma_m, gravity);
  indicators.scans = static_cast<int>(scans_.size());
  indicators.lidar_scans = static_cast<int>(lidar_stamps.size());
  const bool wheels_at_rest = window.wheels_at_rest && window.wheels_at_rest(scans_.front().begin, now);
  if (wheels_at_rest) indicators.lo_speed = 0;
  ModeDecision decision = SelectInitMode(indicators, config_, gravity);
  if (wheels_at_rest && decision.mode == InitMode::kStatic)
    decision.reason += " (the wheels read no motion: the LO speed " +
                       std::to_string(indicators.lo_raw_speed) + " m/s is its noise)";
  record_.mode = decision.mode;
  record_.reason = decision.reason;

  AdmissionCheck check;
  check.verdict = Verdict::kDeferred;
  check.reason = decision.reason;
  if (decision.mode == InitMode::kLidarAided) {
    stamps = std::move(lidar_stamps);
    poses = std::move(lidar_poses);
  } else if (decision.mode == InitMode::kStatic) {
    // S's samples run from the first scan's begin to the newest node: its check covers the same span (the
    // attitudes there: the nearest scan's; at rest they hardly differ).
    if (scans_.front().begin < stamps.front()) {
      stamps.insert(stamps.begin(), scans_.front().begin);
      poses.insert(poses.begin(), poses.front());
    }
    if (now > stamps.back()) {
      stamps.push_back(now);
      poses.push_back(window.node_poses.back());
    }
  }
  std::vector<ImuPreintegration> preintegrations;
  // An attempt that makes no M estimate forgets the previous one.
  const std::optional<Eigen::Vector3d> previous_gravity = std::exchange(previous_gravity_, std::nullopt);
  for (std::size_t k = 1; k < stamps.size() && decision.mode != InitMode::kDeferred; ++k) {
    Expected<ImuPreintegration> pre = imu_.Preintegrate(stamps[k - 1], stamps[k], nullptr);
    if (!pre) {  // a gap (or a hole) in the IMU: the window starts again after it
      check.reason = "IMU: " + pre.status().message() + "; the window starts again after it";
      while (!scans_.empty() && scans_.front().begin < stamps[k]) scans_.pop_front();
      first_allowed_id_ = scans_.empty() ? last_window_id_ + 1 : scans_.front().id;
      break;
    }
    preintegrations.push_back(std::move(*pre));
  }
  if (decision.mode != InitMode::kDeferred && preintegrations.size() + 1 == stamps.size()) {
    Expected<InertialAlignment> alignment = decision.mode == InitMode::kStatic
                                                ? StaticAlignment(indicators, poses, config_, gravity)
                                                : ShortWindowMapAlignment(poses, preintegrations, config_);
    if (alignment) {
      check = CheckAdmission(decision.mode, *alignment, poses, preintegrations, config_, gravity);
      if (decision.mode == InitMode::kLidarAided) {
        previous_gravity_ = GravityDirectionLo(*alignment);
        CheckGravitySettled(previous_gravity, *previous_gravity_, config_, check);
      }
      out.alignment = std::move(*alignment);
    } else {
      check.verdict = Verdict::kRejected;
      check.reason = alignment.status().message();
    }
  }
  out.verdict = check.verdict;
  const char mode = InitModeLetter(decision.mode);
  if (check.verdict == Verdict::kDeferred) {
    if (++record_.deferred == 1)
      out.warning = "LIO initialization deferred at " + StampText(now) + " (" + mode + "): " + check.reason;
    return out;
  }
  if (check.verdict == Verdict::kRejected) {
    const std::string what = StampText(now) + ": " + mode + ": " + check.reason;
    if (++record_.rejected == 1)
      out.warning = "LIO initialization rejected at " + what + "; retrying from the next scan";
    if (static_cast<int>(record_.rejections.size()) < InitializationRecord::kMaxKeptRejections)
      record_.rejections.push_back(what);
    // The oldest scan leaves while more than min_scans remain.
    if (static_cast<int>(scans_.size()) > config_.min_scans) {
      scans_.pop_front();
      first_allowed_id_ = scans_.front().id;
    }
    return out;
  }

  InertialAlignment& a = out.alignment;
  a.velocities = NodeVelocities(a, stamps, poses, window);
  record_.admitted = true;
  ++record_.initializations;
  record_.admitted_at = now;
  record_.latency_s = ToSeconds(now - record_.first_imu);
  record_.scans =
      decision.mode == InitMode::kStatic ? static_cast<int>(scans_.size()) : static_cast<int>(stamps.size());
  record_.gravity_estimate = a.gravity_estimate;
  record_.tilt_sigma_deg = a.tilt_sigma_rad * 180.0 / std::numbers::pi;
  record_.lidar_sigma_m = a.position_sigma_m;
  record_.chi2_per_dof = check.chi2_per_dof;
  record_.R_world_imu = a.R_gravity_lo * window.node_poses.back().so3();
  record_.gravity_imu = record_.R_world_imu.inverse() * Eigen::Vector3d(0, 0, -gravity);
  record_.velocity = a.velocities.back();
  record_.accel_bias = a.accel_bias;
  record_.gyro_bias = a.gyro_bias;
  return out;
}

}  // namespace uf::estimator
