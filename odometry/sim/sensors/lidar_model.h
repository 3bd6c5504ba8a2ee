// Simulated LiDARs on a ray-cast Scene: spinning multi-beam sensors (VLP-16 / HDL-32E / HDL-64E / OS1-128
// like) and a Livox-like non-repetitive solid-state sensor, with rolling acquisition (every firing uses the
// sensor pose at its own time), range noise along the beam, dropout and reflectivity-based intensity.
//
// Frames: world (z up), body (the IMU, moving along the TrajectorySpline T_world_body(t)), lidar (x forward,
// y left, z up) with T_world_lidar(t) = T_world_body(t) * T_body_lidar. Each point is expressed in the lidar
// frame at that point's own time stamp + offset_ns (a raw, not deskewed, scan).
#pragma once

#include <cstdint>
#include <string>

#include "odometry/sim/sensors/lidar_patterns.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::sim {

struct LidarConfig {
  std::string model = "spinning32";  // spinning16 | spinning32 | spinning64 | spinning128 | livox_avia
  double rate_hz = 10.0;             // sweeps (or frames) per second, in [0.5, 100]
  // Spinning only: azimuth step between firings, in (0, 10] deg; the sweep has round(360 / step) columns
  // spread evenly over the turn (1800 columns at 0.2).
  double horizontal_resolution_deg = 0.2;
  double min_range_m = 0.5;          // >= 0: a nearer surface blocks the beam and gives no point
  double max_range_m = 100.0;        // > min_range_m, <= 10000: nothing hit within it gives no point
  double range_noise_std_m = 0.02;   // >= 0, Gaussian, along the beam
  double dropout_probability = 0.0;  // in [0, 1]: each return lost independently
  int threads = 0;                   // >= 0; 0: all cores. Output is identical for any value.
};

// Ok, or an error naming the first bad field and its value ("lidar.rate_hz: must be in [0.5, 100], got -5").
Status ValidateLidarConfig(const LidarConfig& config);

class LidarSimulator {
 public:
  // spline: body (IMU) trajectory T_world_body(t); T_body_lidar: lidar pose in the body frame. The caster
  // and the spline are referenced, not copied: they must outlive the simulator. Fails for a bad config.
  static Expected<LidarSimulator> Create(const LidarConfig& config, const RayCaster& caster,
                                         const TrajectorySpline& spline, const SE3& T_body_lidar,
                                         std::uint64_t seed);

  // The sweep (or Livox frame) that starts at true time `start`: stamp = start, end = start + period(),
  // has_point_times = has_ring = true. Points in acquisition order, in the lidar frame at their own time.
  //   Spinning: column c (of columns()) fires all beams at offset c * period / columns (integer ns) towards
  //   azimuth pi - 2 pi c / columns: clockwise seen from above, starting backwards (-x), as
  //   DerivePointTimesFromAzimuth (odometry/io/folders/point_cloud_files.h) assumes. ring = beam index
  //   (0 = lowest).
  //   Livox: the points n of the rosette with start <= t_n < start + period (lidar_patterns.h);
  //   ring = head.
  // Intensity = round(255 * reflectivity * |cos(incidence)|) in [0, 255], incidence the angle between the
  // beam and the surface normal: a Velodyne-style calibrated intensity of a Lambertian surface.
  // Fails if [start, start + period] is not inside the spline. Deterministic: depends on (seed, start) only.
  Expected<LidarScan> Scan(Stamp start) const;

  const LidarConfig& config() const { return config_; }
  Stamp period() const { return period_; }  // round(1e9 / rate_hz) ns
  double period_s() const { return ToSeconds(period_); }
  bool is_spinning() const { return !elevations_rad_.empty(); }
  int rings() const;                        // beams (spinning) or heads (Livox)
  int columns() const { return columns_; }  // firings per sweep (spinning only; 0 for Livox)
  const std::vector<double>& elevations_rad() const { return elevations_rad_; }  // spinning, by ring
  const SE3& T_body_lidar() const { return T_body_lidar_; }

 private:
  LidarSimulator() = default;
  Expected<LidarScan> ScanSpinning(Stamp start) const;
  Expected<LidarScan> ScanLivox(Stamp start) const;

  LidarConfig config_;
  const RayCaster* caster_ = nullptr;
  const TrajectorySpline* spline_ = nullptr;
  SE3 T_body_lidar_;
  std::uint64_t seed_ = 0;
  Stamp period_ = 0;
  int columns_ = 0;
  std::vector<double> elevations_rad_;
};

}  // namespace uf::sim
