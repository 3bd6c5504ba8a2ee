#include "odometry/sim/gnss_model.h"

#include <array>
#include <cassert>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "odometry/sim/sampling.h"

namespace uf::sim {
namespace {

// Indexed by the enum's value.
constexpr GnssQuality kQualities[] = {GnssQuality::kRtkFixed, GnssQuality::kRtkFloat, GnssQuality::kSingle};
static_assert(static_cast<int>(GnssQuality::kRtkFixed) == 0 &&
              static_cast<int>(GnssQuality::kRtkFloat) == 1 && static_cast<int>(GnssQuality::kSingle) == 2);

bool IsQuality(GnssQuality quality) {
  return quality == GnssQuality::kRtkFixed || quality == GnssQuality::kRtkFloat ||
         quality == GnssQuality::kSingle;
}

Status CheckWindow(const std::string& name, const TimeWindow& window) {
  if (window.end >= window.begin) return Status();
  return Status::Error(name + ": end " + FormatSeconds(window.end) + " s is before begin " +
                       FormatSeconds(window.begin) + " s");
}

Status CheckNoise(const std::string& name, const GnssNoise& noise) {
  const std::pair<const char*, double> values[] = {{"horizontal_std_m", noise.horizontal_std_m},
                                                   {"vertical_std_m", noise.vertical_std_m},
                                                   {"correlation_time_s", noise.correlation_time_s}};
  for (const auto& [field, value] : values) {
    if (!std::isfinite(value) || value < 0.0) {
      return Status::Error(name + "." + field + ": must be finite and >= 0, got " + NumberText(value));
    }
  }
  return Status();
}

}  // namespace

GnssFixStatus ToFixStatus(GnssQuality quality) {
  switch (quality) {
    case GnssQuality::kRtkFixed:
      return GnssFixStatus::kRtkFixed;
    case GnssQuality::kRtkFloat:
      return GnssFixStatus::kRtkFloat;
    case GnssQuality::kSingle:
      return GnssFixStatus::kFix;
  }
  assert(false && "unknown GnssQuality");
  return GnssFixStatus::kNoFix;
}

const GnssNoise& GnssConfig::Noise(GnssQuality quality) const {
  switch (quality) {
    case GnssQuality::kRtkFixed:
      return rtk_fixed;
    case GnssQuality::kRtkFloat:
      return rtk_float;
    case GnssQuality::kSingle:
      return single;
  }
  assert(false && "unknown GnssQuality");
  return single;
}

GnssQuality GnssConfig::QualityAt(Stamp t) const {
  GnssQuality result = quality;
  for (const auto& [window, window_quality] : quality_changes) {
    if (window.Contains(t)) result = window_quality;  // the last listed wins
  }
  return result;
}

Status GnssConfig::Validate() const {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0 || rate_hz > 1000.0) {
    return Status::Error("gnss.rate_hz: must be in (0, 1000], got " + NumberText(rate_hz));
  }
  if (!IsQuality(quality)) {
    return Status::Error("gnss.quality: unknown value " + std::to_string(static_cast<int>(quality)));
  }
  for (std::size_t i = 0; i < quality_changes.size(); ++i) {
    const std::string name = "gnss.quality_changes[" + std::to_string(i) + "]";
    if (Status status = CheckWindow(name + ".window", quality_changes[i].first); !status.ok()) return status;
    if (!IsQuality(quality_changes[i].second)) {
      return Status::Error(name + ".quality: unknown value " +
                           std::to_string(static_cast<int>(quality_changes[i].second)));
    }
  }
  for (std::size_t i = 0; i < outages.size(); ++i) {
    if (Status status = CheckWindow("gnss.outages[" + std::to_string(i) + "]", outages[i]); !status.ok()) {
      return status;
    }
  }
  for (std::size_t i = 0; i < multipath.size(); ++i) {
    const std::string name = "gnss.multipath[" + std::to_string(i) + "]";
    if (Status status = CheckWindow(name + ".window", multipath[i].first); !status.ok()) return status;
    if (!multipath[i].second.allFinite()) {
      const Eigen::Vector3d& offset = multipath[i].second;
      return Status::Error(name + ".offset: must be finite, got (" + NumberText(offset.x()) + ", " +
                           NumberText(offset.y()) + ", " + NumberText(offset.z()) + ")");
    }
  }
  const std::pair<const char*, const GnssNoise*> noises[] = {
      {"gnss.rtk_fixed", &rtk_fixed}, {"gnss.rtk_float", &rtk_float}, {"gnss.single", &single}};
  for (const auto& [name, noise] : noises) {
    if (Status status = CheckNoise(name, *noise); !status.ok()) return status;
  }
  return Status();
}

Expected<GnssSimulator> GnssSimulator::Create(TrajectorySpline trajectory, const SE3& T_body_antenna,
                                              const GnssConfig& config, const GeodeticOrigin& origin,
                                              std::uint64_t seed) {
  if (Status status = config.Validate(); !status.ok()) return status;
  if (Status status = ValidateGeodeticOrigin(origin); !status.ok()) {
    return Status::Error("gnss." + status.message());
  }
  if (!T_body_antenna.matrix().allFinite())
    return Status::Error("gnss extrinsic T_body_antenna must be finite");
  return GnssSimulator(std::move(trajectory), T_body_antenna, config, origin, seed);
}

GnssSimulator::GnssSimulator(TrajectorySpline trajectory, const SE3& T_body_antenna, const GnssConfig& config,
                             const GeodeticOrigin& origin, std::uint64_t seed)
    : trajectory_(std::move(trajectory)),
      T_body_antenna_(T_body_antenna),
      config_(config),
      origin_(origin),
      seed_(seed) {}

Eigen::Vector3d GnssSimulator::TrueAntennaEnu(Stamp t) const {
  return trajectory_.Evaluate(t).T_world_body * T_body_antenna_.translation();
}

Expected<SimulatedGnss> GnssSimulator::Generate(Stamp begin, Stamp end) const {
  if (Status s = sim::CheckSampleInterval("gnss", trajectory_, begin, end, config_.rate_hz); !s.ok())
    return s;
  const long double period_ns = 1e9L / static_cast<long double>(config_.rate_hz);

  // One unit-variance Gauss-Markov state per quality (index as in kQualities), all stepped at every sample
  // with draws in a fixed order (quality by quality, east, north, up), so outages, quality changes and
  // multipath never shift the random sequence.
  std::mt19937_64 engine(seed_);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::array<Eigen::Vector3d, 3> state;
  SimulatedGnss out;
  Stamp previous_stamp = begin;
  for (std::int64_t k = 0;; ++k) {
    // Each stamp rounded on its own, so a period that is not a whole number of ns does not drift.
    const Stamp stamp = GridStamp(begin, period_ns, k);
    if (stamp > end) break;
    for (std::size_t q = 0; q < state.size(); ++q) {
      const double tau = config_.Noise(kQualities[q]).correlation_time_s;
      // a = exp(-dt / tau); the first sample (and white noise) a = 0: a fresh stationary draw.
      const double a = (k == 0 || tau == 0.0) ? 0.0 : std::exp(-ToSeconds(stamp - previous_stamp) / tau);
      Eigen::Vector3d draw;
      for (int axis = 0; axis < 3; ++axis) draw(axis) = normal(engine);  // in order: east, north, up
      state[q] = k == 0 ? draw : Eigen::Vector3d(a * state[q] + std::sqrt(1.0 - a * a) * draw);
    }
    previous_stamp = stamp;

    bool in_outage = false;
    for (const TimeWindow& outage : config_.outages) in_outage = in_outage || outage.Contains(stamp);
    if (in_outage) continue;

    const GnssQuality quality = config_.QualityAt(stamp);
    const GnssNoise& noise = config_.Noise(quality);
    const auto q = static_cast<std::size_t>(quality);
    const Eigen::Vector3d sigma(noise.horizontal_std_m, noise.horizontal_std_m, noise.vertical_std_m);
    Eigen::Vector3d measured = TrueAntennaEnu(stamp);
    out.true_enu.push_back(measured);
    measured += sigma.cwiseProduct(state[q]);
    for (const auto& [window, offset] : config_.multipath) {
      if (window.Contains(stamp)) measured += offset;
    }

    const Eigen::Vector3d lat_lon_h = GeodeticFromEnu(origin_, measured);
    GnssFix fix;
    fix.stamp = stamp;
    fix.latitude_deg = lat_lon_h.x();
    fix.longitude_deg = lat_lon_h.y();
    fix.altitude_m = lat_lon_h.z();
    fix.covariance_enu = sigma.cwiseAbs2().asDiagonal();
    fix.status = ToFixStatus(quality);
    out.fixes.push_back(fix);
  }
  return out;
}

}  // namespace uf::sim
