// ExpectSameConfig: gtest expectations that two SimulationConfigs agree in every field that the `sim:`
// section of a configuration file maps, exactly (doubles bit for bit) unless a tolerance is given.
#pragma once

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "odometry/sim/sequence/simulation_config.h"

namespace uf::app::test {

using sim::SimulationConfig;
using sim::TimeWindow;

#define EXPECT_FIELD(field) EXPECT_EQ(a.field, b.field) << #field

inline void ExpectSameWindows(const std::vector<TimeWindow>& a, const std::vector<TimeWindow>& b,
                              const char* name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].begin, b[i].begin) << name << "[" << i << "]";
    EXPECT_EQ(a[i].end, b[i].end) << name << "[" << i << "]";
  }
}

template <typename T>
inline void ExpectSameEvents(const std::vector<std::pair<TimeWindow, T>>& a,
                             const std::vector<std::pair<TimeWindow, T>>& b, const char* name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].first.begin, b[i].first.begin) << name << "[" << i << "]";
    EXPECT_EQ(a[i].first.end, b[i].first.end) << name << "[" << i << "]";
    EXPECT_EQ(a[i].second, b[i].second) << name << "[" << i << "]";
  }
}

// `tolerance` applies to the extrinsics' matrices only (0: bit-identical); everything else is exact.
inline void ExpectSamePlacement(const sim::SensorPlacement& a, const sim::SensorPlacement& b,
                                const char* sensor, double tolerance) {
  const Eigen::Matrix4d difference = a.T_body_sensor.matrix() - b.T_body_sensor.matrix();
  EXPECT_LE(difference.cwiseAbs().maxCoeff(), tolerance) << sensor << ".extrinsic\n"
                                                         << a.T_body_sensor.matrix() << "\nvs\n"
                                                         << b.T_body_sensor.matrix();
  EXPECT_FIELD(stamp_delay_s) << " of " << sensor;
  EXPECT_FIELD(rotation_error_deg) << " of " << sensor;
  EXPECT_FIELD(translation_error_m) << " of " << sensor;
}

inline void ExpectSameNoise(const sim::GnssNoise& a, const sim::GnssNoise& b, const char* quality) {
  EXPECT_FIELD(horizontal_std_m) << " of " << quality;
  EXPECT_FIELD(vertical_std_m) << " of " << quality;
  EXPECT_FIELD(correlation_time_s) << " of " << quality;
}

// Every field the file maps (the models' `threads` are not in the file).
inline void ExpectSameConfig(const SimulationConfig& a, const SimulationConfig& b,
                             double extrinsic_tolerance = 0.0) {
  EXPECT_FIELD(scene);
  EXPECT_FIELD(seed);
  EXPECT_FIELD(duration_s);
  EXPECT_FIELD(start_stamp);
  EXPECT_FIELD(trajectory.file);
  EXPECT_FIELD(trajectory.format);
  EXPECT_FIELD(trajectory.kitti_rate_hz);
  EXPECT_FIELD(trajectory.knot_spacing_s);
  EXPECT_FIELD(body_height_m);
  EXPECT_FIELD(ground_truth_rate_hz);
  EXPECT_FIELD(origin.latitude_deg);
  EXPECT_FIELD(origin.longitude_deg);
  EXPECT_FIELD(origin.height_m);
  EXPECT_FIELD(threads);
  EXPECT_FIELD(write_bag);

  EXPECT_FIELD(imu.enabled);
  EXPECT_FIELD(imu.rate_hz);
  EXPECT_FIELD(imu.noise.accel_noise_density);
  EXPECT_FIELD(imu.noise.gyro_noise_density);
  EXPECT_FIELD(imu.noise.accel_bias_random_walk);
  EXPECT_FIELD(imu.noise.gyro_bias_random_walk);
  EXPECT_FIELD(imu.noise.initial_accel_bias);
  EXPECT_FIELD(imu.noise.initial_gyro_bias);
  EXPECT_FIELD(imu.noise.accel_saturation);
  EXPECT_FIELD(imu.noise.gyro_saturation);

  EXPECT_FIELD(lidar.enabled);
  EXPECT_FIELD(lidar.model.model);
  EXPECT_FIELD(lidar.model.rate_hz);
  EXPECT_FIELD(lidar.model.horizontal_resolution_deg);
  EXPECT_FIELD(lidar.model.min_range_m);
  EXPECT_FIELD(lidar.model.max_range_m);
  EXPECT_FIELD(lidar.model.range_noise_std_m);
  EXPECT_FIELD(lidar.model.dropout_probability);
  ExpectSamePlacement(a.lidar.placement, b.lidar.placement, "lidar", extrinsic_tolerance);

  const sim::CameraConfig &ca = a.camera.model, &cb = b.camera.model;
  EXPECT_FIELD(camera.enabled);
  EXPECT_EQ(ca.pinhole.width, cb.pinhole.width);
  EXPECT_EQ(ca.pinhole.height, cb.pinhole.height);
  for (auto field :
       {&PinholeIntrinsics::fx, &PinholeIntrinsics::fy, &PinholeIntrinsics::cx, &PinholeIntrinsics::cy})
    EXPECT_EQ(ca.pinhole.*field, cb.pinhole.*field);
  for (auto field :
       {&sim::CameraConfig::k1, &sim::CameraConfig::k2, &sim::CameraConfig::p1, &sim::CameraConfig::p2,
        &sim::CameraConfig::k3, &sim::CameraConfig::rate_hz, &sim::CameraConfig::noise_std_dn,
        &sim::CameraConfig::ambient, &sim::CameraConfig::exposure})
    EXPECT_EQ(ca.*field, cb.*field);
  EXPECT_EQ(ca.supersampling, cb.supersampling);
  EXPECT_EQ(ca.textured, cb.textured);
  EXPECT_EQ(ca.sun_direction_world, cb.sun_direction_world);
  ExpectSameWindows(ca.darkness, cb.darkness, "camera.darkness");
  ExpectSameEvents(ca.exposure_changes, cb.exposure_changes, "camera.exposure_changes");
  ExpectSameWindows(ca.occlusions, cb.occlusions, "camera.occlusions");
  ExpectSamePlacement(a.camera.placement, b.camera.placement, "camera", extrinsic_tolerance);

  EXPECT_FIELD(wheel.enabled);
  EXPECT_FIELD(wheel.model.rate_hz);
  EXPECT_FIELD(wheel.model.wheel_radius_m);
  EXPECT_FIELD(wheel.model.baseline_m);
  EXPECT_FIELD(wheel.model.radius_error);
  EXPECT_FIELD(wheel.model.baseline_error);
  EXPECT_FIELD(wheel.model.encoder_resolution_ticks);
  EXPECT_FIELD(wheel.model.wheel_speed_noise_std);
  ExpectSameEvents(a.wheel.model.slips, b.wheel.model.slips, "wheel.slips");
  ExpectSameWindows(a.wheel.model.floats, b.wheel.model.floats, "wheel.floats");
  ExpectSamePlacement(a.wheel.placement, b.wheel.placement, "wheel", extrinsic_tolerance);

  EXPECT_FIELD(gnss.enabled);
  EXPECT_FIELD(gnss.model.rate_hz);
  EXPECT_FIELD(gnss.model.quality);
  ExpectSameEvents(a.gnss.model.quality_changes, b.gnss.model.quality_changes, "gnss.quality_changes");
  ExpectSameWindows(a.gnss.model.outages, b.gnss.model.outages, "gnss.outages");
  ExpectSameEvents(a.gnss.model.multipath, b.gnss.model.multipath, "gnss.multipath");
  ExpectSameNoise(a.gnss.model.rtk_fixed, b.gnss.model.rtk_fixed, "rtk_fixed");
  ExpectSameNoise(a.gnss.model.rtk_float, b.gnss.model.rtk_float, "rtk_float");
  ExpectSameNoise(a.gnss.model.single, b.gnss.model.single, "single");
  ExpectSamePlacement(a.gnss.placement, b.gnss.placement, "gnss", extrinsic_tolerance);
}

#undef EXPECT_FIELD

}  // namespace uf::app::test
