// Simulated GNSS receiver on a TrajectorySpline: WGS84 position fixes of an antenna mounted at
// T_body_antenna, with a quality (RTK fixed / RTK float / single point) that can change over time, outages
// and multipath offsets.
//
// The world frame is ENU at a GeodeticOrigin (odometry/types/geodetic.h). True antenna position:
//   p_enu = T_world_body * r,  r = translation of T_body_antenna (the antenna's orientation does not matter)
// Reported: GeodeticFromEnu(origin, p_enu + e(t) + m(t)), with m the multipath offset of the windows that
// contain t and e the error of the current quality q:
//   e = (sigma_h(q) x_e, sigma_h(q) x_n, sigma_v(q) x_u)
// where x = (x_e, x_n, x_u) is a unit-variance first-order Gauss-Markov process per quality, with
// correlation time tau(q) (autocorrelation exp(-|dt| / tau)), stepped at every sample (also in outages):
//   x_k = a x_{k-1} + sqrt(1 - a^2) n_k,  a = exp(-(t_k - t_{k-1}) / tau),  n_k ~ N(0, I),  x_0 ~ N(0, I)
// (tau = 0: a = 0, white noise). So a single-point fix wanders slowly instead of jumping, each quality's
// error has its nominal statistics whatever the switching, and the reported covariance_enu is the nominal
// diag(sigma_h^2, sigma_h^2, sigma_v^2) of the quality.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "odometry/sim/time_window.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/geodetic.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::sim {

enum class GnssQuality { kRtkFixed, kRtkFloat, kSingle };

// kRtkFixed -> GnssFixStatus::kRtkFixed, kRtkFloat -> kRtkFloat, kSingle -> kFix.
GnssFixStatus ToFixStatus(GnssQuality quality);

// Error of one quality (1 sigma, all finite and >= 0).
struct GnssNoise {
  double horizontal_std_m = 0.0;    // per horizontal axis: east and north each
  double vertical_std_m = 0.0;      // up
  double correlation_time_s = 0.0;  // tau of the Gauss-Markov process; 0 = white (independent fixes)
};

struct GnssConfig {
  double rate_hz = 5.0;                        // fixes per second, in (0, 1000]
  GnssQuality quality = GnssQuality::kSingle;  // outside every quality change window
  // Window -> quality inside it; where windows overlap, the last listed that contains the time decides.
  std::vector<std::pair<TimeWindow, GnssQuality>> quality_changes;
  std::vector<TimeWindow> outages;  // no fixes inside (the error processes run on)
  // Window -> ENU offset (m, finite) added to the fixes inside; overlapping offsets add up.
  std::vector<std::pair<TimeWindow, Eigen::Vector3d>> multipath;
  GnssNoise rtk_fixed{0.02, 0.04, 2.0};
  GnssNoise rtk_float{0.3, 0.5, 10.0};
  GnssNoise single{1.5, 3.0, 30.0};

  const GnssNoise& Noise(GnssQuality quality) const;
  // The quality in force at t (quality_changes over the default).
  GnssQuality QualityAt(Stamp t) const;
  // Fails naming the field and value, e.g. "gnss.rate_hz: must be in (0, 1000], got -5".
  Status Validate() const;
};

struct SimulatedGnss {
  std::vector<GnssFix> fixes;             // what the receiver reports
  std::vector<Eigen::Vector3d> true_enu;  // the true antenna position (world = ENU, m), one per fix
};

class GnssSimulator {
 public:
  // Fails for an invalid config (see GnssConfig::Validate) or origin (ValidateGeodeticOrigin), or a
  // non-finite T_body_antenna.
  static Expected<GnssSimulator> Create(TrajectorySpline trajectory, const SE3& T_body_antenna,
                                        const GnssConfig& config, const GeodeticOrigin& origin,
                                        std::uint64_t seed);

  // The true antenna position in the world (ENU) at t; asserts that the trajectory covers t.
  Eigen::Vector3d TrueAntennaEnu(Stamp t) const;

  // Fixes at begin + round(k * 1e9 / rate_hz) ns up to end, except in outages. Each call starts again from
  // the seed, so the output depends only on the arguments. Fails when [begin, end] is empty or not inside
  // the trajectory.
  Expected<SimulatedGnss> Generate(Stamp begin, Stamp end) const;

  const TrajectorySpline& trajectory() const { return trajectory_; }
  const SE3& T_body_antenna() const { return T_body_antenna_; }
  const GnssConfig& config() const { return config_; }
  const GeodeticOrigin& origin() const { return origin_; }

 private:
  GnssSimulator(TrajectorySpline trajectory, const SE3& T_body_antenna, const GnssConfig& config,
                const GeodeticOrigin& origin, std::uint64_t seed);

  TrajectorySpline trajectory_;
  SE3 T_body_antenna_;
  GnssConfig config_;
  GeodeticOrigin origin_;
  std::uint64_t seed_;
};

}  // namespace uf::sim
