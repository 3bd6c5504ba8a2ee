// gtest expectations that two settings agree in every field that a section of the configuration file maps,
// exactly (doubles bit for bit), written out field by field: ExpectSameConfig (sim:, a tolerance for the
// extrinsics allowed), ExpectSameDataset (dataset:), ExpectSameLo / ExpectSameLio / ExpectSameWio (lo:, lio:,
// wio:) and ExpectSameSplat (splat:).
#pragma once

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "odometry/sim/sequence/simulation_config.h"
#include "viewer/app/config/config_file.h"

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
  EXPECT_FIELD(trajectory.motion);
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
  EXPECT_FIELD(lidar.keyframe_rate_hz);
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
  ExpectSameWindows(ca.passing_panels, cb.passing_panels, "camera.passing_panels");
  ExpectSamePlacement(a.camera.placement, b.camera.placement, "camera", extrinsic_tolerance);
  EXPECT_FIELD(camera.stereo_baseline_m);

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

inline void ExpectSameDataset(const DatasetConfig& a, const DatasetConfig& b) {
  EXPECT_FIELD(reader.format);
  ASSERT_EQ(a.reader.topics.size(), b.reader.topics.size());
  for (std::size_t i = 0; i < a.reader.topics.size(); ++i) {
    EXPECT_FIELD(reader.topics[i].topic);
    EXPECT_FIELD(reader.topics[i].kind);
    ASSERT_EQ(a.reader.topics[i].T_body_sensor.has_value(), b.reader.topics[i].T_body_sensor.has_value());
    if (a.reader.topics[i].T_body_sensor) {  // exact: the matrix is written with every digit
      EXPECT_EQ(a.reader.topics[i].T_body_sensor->matrix(), b.reader.topics[i].T_body_sensor->matrix());
    }
  }
  EXPECT_FIELD(reader.imu_accel_unit);
  EXPECT_FIELD(reader.derive_point_times_from_azimuth);
  EXPECT_FIELD(reader.point_time_convention);
  EXPECT_FIELD(reader.lidar_sweep_period_s);
  EXPECT_FIELD(reader.folder_scan_stamp);
  EXPECT_FIELD(reader.calibration_file);
  EXPECT_FIELD(stream.time_offsets);
  EXPECT_FIELD(stream.reorder_window);
}

// The keys of lo: (not T_body_lidar, use_imu and marginalization, which have none).
inline void ExpectSameLo(const estimator::LidarOdometryConfig& a, const estimator::LidarOdometryConfig& b) {
  EXPECT_FIELD(input_voxel_m);
  EXPECT_FIELD(window_size);
  EXPECT_FIELD(max_iterations);
  EXPECT_FIELD(max_solver_time_s);
  EXPECT_FIELD(condensed_lidar_rounds);
  EXPECT_FIELD(max_residuals_per_scan);
  EXPECT_FIELD(huber_m);
  EXPECT_FIELD(min_range_m);
  EXPECT_FIELD(max_range_m);
  EXPECT_FIELD(map_insert_voxel_m);
  EXPECT_FIELD(association_rounds);
  EXPECT_FIELD(min_match_ratio);
  EXPECT_FIELD(max_speed_mps);
  EXPECT_FIELD(max_angular_rate_rad_s);
  EXPECT_FIELD(max_rejected_scans);
  EXPECT_FIELD(max_prediction_s);
  EXPECT_FIELD(min_points);
  EXPECT_FIELD(max_plane_distance_m);
  EXPECT_FIELD(marginalize);
  EXPECT_FIELD(drop_weak_directions);
  EXPECT_FIELD(motion.acc_density);
  EXPECT_FIELD(motion.angular_acc_density);
  EXPECT_FIELD(motion.sweep_acc_density);
  EXPECT_FIELD(map.voxel_m);
  EXPECT_FIELD(map.max_points_per_voxel);
  EXPECT_FIELD(map.max_range_m);
  EXPECT_FIELD(map.plane_eigen_ratio);
  EXPECT_FIELD(map.min_plane_points);
  EXPECT_FIELD(map.min_plane_sigma_m);
  EXPECT_FIELD(map.neighbour_weight);
  EXPECT_FIELD(map.min_plane_rings);
}

// The parts that lio: and wio: share: imu, init (but its LIO-only keys), wheel, gnss, visual.
template <typename Config>
inline void ExpectSameInertialParts(const Config& a, const Config& b) {
  EXPECT_FIELD(imu.accel_noise_density);
  EXPECT_FIELD(imu.gyro_noise_density);
  EXPECT_FIELD(imu.accel_bias_random_walk);
  EXPECT_FIELD(imu.gyro_bias_random_walk);
  EXPECT_FIELD(imu.gravity);
  EXPECT_FIELD(imu.max_accel_bias_change);
  EXPECT_FIELD(imu.max_gyro_bias_change);
  EXPECT_FIELD(imu.gyro_range);
  EXPECT_FIELD(imu.accel_range);
  EXPECT_FIELD(init.static_max_gyro_std);
  EXPECT_FIELD(init.static_max_vibration_deg);
  EXPECT_FIELD(init.static_max_acc_std);
  EXPECT_FIELD(init.static_min_duration_s);
  EXPECT_FIELD(init.static_max_speed_mps);
  EXPECT_FIELD(init.max_gravity_error);
  EXPECT_FIELD(wheel.forward_velocity_density);
  EXPECT_FIELD(wheel.yaw_rate_density);
  EXPECT_FIELD(wheel.nonholonomic_velocity_density);
  EXPECT_FIELD(wheel.suspension_tilt_sigma);
  EXPECT_FIELD(wheel.tilt_per_acceleration);
  EXPECT_FIELD(wheel.roll_pitch_rate_density);
  EXPECT_FIELD(wheel.max_gap_s);
  EXPECT_FIELD(wheel.time_offset_s);
  EXPECT_FIELD(wheel.estimate_scale);
  EXPECT_FIELD(wheel.scale_prior_sigma);
  EXPECT_FIELD(wheel.stationary_updates);
  EXPECT_FIELD(wheel.schedule.enabled);
  EXPECT_FIELD(wheel.schedule.speed_tolerance_mps);
  EXPECT_FIELD(wheel.schedule.yaw_rate_tolerance_rad_s);
  EXPECT_FIELD(wheel.schedule.drift_mps_per_s);
  EXPECT_FIELD(wheel.schedule.baseline_time_s);
  EXPECT_FIELD(wheel.schedule.change_window_s);
  EXPECT_FIELD(wheel.schedule.change_tolerance_mps);
  EXPECT_FIELD(wheel.schedule.max_shut_s);
  EXPECT_FIELD(wheel.schedule.speed_weight);
  EXPECT_FIELD(wheel.schedule.threshold);
  EXPECT_FIELD(wheel.schedule.release_margin);
  EXPECT_FIELD(wheel.schedule.release_keyframes);
  EXPECT_FIELD(gnss.min_status);
  for (const auto noise :
       {&estimator::GnssFactorConfig::fix, &estimator::GnssFactorConfig::sbas,
        &estimator::GnssFactorConfig::rtk_float, &estimator::GnssFactorConfig::rtk_fixed}) {
    EXPECT_EQ((a.gnss.*noise).min_sigma_m, (b.gnss.*noise).min_sigma_m);
    EXPECT_EQ((a.gnss.*noise).sigma_scale, (b.gnss.*noise).sigma_scale);
    EXPECT_EQ((a.gnss.*noise).nominal_horizontal_sigma_m, (b.gnss.*noise).nominal_horizontal_sigma_m);
    EXPECT_EQ((a.gnss.*noise).nominal_vertical_sigma_m, (b.gnss.*noise).nominal_vertical_sigma_m);
    EXPECT_EQ((a.gnss.*noise).offset_share, (b.gnss.*noise).offset_share);
  }
  EXPECT_FIELD(gnss.offset_correlation_time_s);
  EXPECT_FIELD(gnss.use_nominal_for_unknown);
  EXPECT_FIELD(gnss.integrity_gate);
  EXPECT_FIELD(gnss.prediction_sigma_m);
  EXPECT_FIELD(gnss.prediction_drift_fraction);
  EXPECT_FIELD(gnss.step_max_hold_s);
  EXPECT_FIELD(gnss.min_alignment_baseline_m);
  EXPECT_FIELD(gnss.min_alignment_fixes);
  EXPECT_FIELD(gnss.max_alignment_rms_m);
  EXPECT_FIELD(gnss.max_interpolation_gap_s);
  EXPECT_FIELD(gnss.max_snap_s);
  EXPECT_FIELD(visual.pixel_sigma_px);
  EXPECT_FIELD(visual.huber_sigmas);
  EXPECT_FIELD(visual.min_parallax_deg);
  EXPECT_FIELD(visual.min_depth_m);
  EXPECT_FIELD(visual.max_depth_m);
  EXPECT_FIELD(visual.max_reprojection_px);
  EXPECT_FIELD(visual.hold_map_depth);
  EXPECT_FIELD(visual.time_offset_s);
  EXPECT_FIELD(visual.estimate_time_offset);
  EXPECT_FIELD(visual.time_offset_sigma_s);
  EXPECT_FIELD(visual.estimate_extrinsic);
  EXPECT_FIELD(visual.extrinsic_rotation_sigma_deg);
  EXPECT_FIELD(visual.extrinsic_translation_sigma_m);
  EXPECT_FIELD(visual.max_iterations);
  EXPECT_FIELD(visual.max_solver_time_s);
  EXPECT_FIELD(visual.max_static_flow_px);
  EXPECT_FIELD(visual.tracker.max_features);
  EXPECT_FIELD(visual.tracker.min_distance_px);
  EXPECT_FIELD(visual.tracker.quality_level);
  EXPECT_FIELD(visual.tracker.klt_window_px);
  EXPECT_FIELD(visual.tracker.klt_pyramid_levels);
  EXPECT_FIELD(visual.tracker.max_fb_error_px);
  EXPECT_FIELD(visual.tracker.ransac_threshold_px);
  EXPECT_FIELD(visual.tracker.ransac_confidence);
  EXPECT_FIELD(visual.tracker.min_track_length);
  EXPECT_FIELD(visual.tracker.keyframe_parallax_px);
  EXPECT_FIELD(visual.tracker.grid_cells);
  EXPECT_FIELD(visual.tracker.min_contrast_dn);
  EXPECT_FIELD(visual.tracker.normalize_exposure);
  EXPECT_FIELD(visual.tracker.smoothing_sigma_px);
  EXPECT_FIELD(visual.schedule.enabled);
  EXPECT_FIELD(visual.schedule.tolerance_px);
  EXPECT_FIELD(visual.schedule.min_tracks);
  EXPECT_FIELD(visual.schedule.reference_tracks);
  EXPECT_FIELD(visual.schedule.residual_threshold_px);
  EXPECT_FIELD(visual.schedule.threshold);
  EXPECT_FIELD(visual.schedule.release_margin);
  EXPECT_FIELD(visual.schedule.release_frames);
  EXPECT_FIELD(visual.schedule.max_shut_s);
}

inline void ExpectSameLio(const estimator::LidarOdometryConfig& a, const estimator::LidarOdometryConfig& b) {
  EXPECT_FIELD(imu_deskew);
  EXPECT_FIELD(estimate_lidar_translation);
  EXPECT_FIELD(lidar_translation_sigma_m);
  EXPECT_FIELD(lidar_translation_min_turn_deg);
  EXPECT_FIELD(wheel_carries_weak_translations);
  EXPECT_FIELD(imu_max_gap_s);
  EXPECT_FIELD(imu_max_wait_s);
  EXPECT_FIELD(init.min_scans);
  EXPECT_FIELD(init.map_settle_scans);
  EXPECT_FIELD(init.max_scans);
  EXPECT_FIELD(init.max_tilt_sigma_deg);
  EXPECT_FIELD(init.lidar_position_sigma_m);
  EXPECT_FIELD(init.accel_bias_sigma);
  EXPECT_FIELD(init.max_chi2_per_dof);
  ExpectSameInertialParts(a, b);
}

// The keys of wio: (not T_body_wheel, T_body_gnss, T_body_camera, camera, use_wheel, use_camera, use_gnss and
// marginalization, which have none).
inline void ExpectSameWio(const estimator::InertialOdometryConfig& a,
                          const estimator::InertialOdometryConfig& b) {
  EXPECT_FIELD(node_interval_s);
  EXPECT_FIELD(window_size);
  EXPECT_FIELD(init_window_nodes);
  EXPECT_FIELD(max_iterations);
  EXPECT_FIELD(max_solver_time_s);
  EXPECT_FIELD(marginalize);
  EXPECT_FIELD(init_accel_bias_sigma);
  EXPECT_FIELD(init_gyro_bias_sigma);
  EXPECT_FIELD(imu_max_gap_s);
  EXPECT_FIELD(max_speed_mps);
  EXPECT_FIELD(wheel_max_wait_s);
  ExpectSameInertialParts(a, b);
}

inline void ExpectSameSplat(const SplatConfig& a, const SplatConfig& b) {
  EXPECT_FIELD(time_budget_s);
  EXPECT_FIELD(width);
  EXPECT_FIELD(height);
  EXPECT_FIELD(max_width);
  EXPECT_FIELD(coarse_to_fine_interval);
  EXPECT_FIELD(keyframe_distance_m);
  EXPECT_FIELD(keyframe_angle_deg);
  EXPECT_FIELD(holdout_stride);
  EXPECT_FIELD(comparisons);
  EXPECT_FIELD(seed_points);
  EXPECT_FIELD(feature_seed_corners);
  EXPECT_FIELD(sky_gaussians);
  EXPECT_FIELD(mask_image);
  EXPECT_FIELD(exposure_compensation);
  EXPECT_FIELD(exposure_from);
  EXPECT_FIELD(exposure_prior);
  EXPECT_FIELD(training.iterations);
  EXPECT_FIELD(training.sh_degree);
  EXPECT_FIELD(training.sh_degree_interval);
  EXPECT_FIELD(training.lr_position_initial);
  EXPECT_FIELD(training.lr_position_final);
  EXPECT_FIELD(training.lr_log_scale);
  EXPECT_FIELD(training.lr_rotation);
  EXPECT_FIELD(training.lr_opacity);
  EXPECT_FIELD(training.lr_sh_dc);
  EXPECT_FIELD(training.lr_sh_rest);
  EXPECT_FIELD(training.adam_beta1);
  EXPECT_FIELD(training.adam_beta2);
  EXPECT_FIELD(training.adam_epsilon);
  EXPECT_FIELD(training.ssim_weight);
  EXPECT_FIELD(training.depth_weight);
  EXPECT_FIELD(training.densify_from);
  EXPECT_FIELD(training.densify_until);
  EXPECT_FIELD(training.densify_interval);
  EXPECT_FIELD(training.densify_gradient_threshold);
  EXPECT_FIELD(training.dense_fraction);
  EXPECT_FIELD(training.prune_opacity);
  EXPECT_FIELD(training.prune_world_fraction);
  EXPECT_FIELD(training.opacity_reset_interval);
  EXPECT_FIELD(training.max_gaussians);
  EXPECT_FIELD(training.render.background);
  EXPECT_FIELD(training.seed);
}

#undef EXPECT_FIELD

}  // namespace uf::app::test
