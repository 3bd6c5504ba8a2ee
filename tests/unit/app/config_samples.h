// Settings with a value other than the default in every field that a section of the configuration file
// maps, for round trips that must move every field: NonDefaultConfig (sim:), NonDefaultDataset,
// NonDefaultOdometry (lo: and lio:), NonDefaultWio (wio:) and NonDefaultSplat. Each passes its section's
// checks.
#pragma once

#include "odometry/sim/sequence/simulation_config.h"
#include "viewer/app/config/config_file.h"

namespace uf::app::test {

using sim::GnssQuality;
using sim::SimulationConfig;
using sim::TimeWindow;

// [begin_s, end_s] after `start`, exact nanoseconds.
inline TimeWindow Window(Stamp start, Stamp begin_ns, Stamp end_ns) {
  return {start + begin_ns, start + end_ns};
}

inline SE3 Pose(double rx, double ry, double rz, double x, double y, double z) {
  return SE3(SO3::Exp(Eigen::Vector3d(rx, ry, rz)), Eigen::Vector3d(x, y, z));
}

// A value other than the default in every field, with awkward doubles (1/3, 0.1 + 0.2, 1e-300, 2^-1074).
inline SimulationConfig NonDefaultConfig() {
  SimulationConfig c;
  c.scene = "weird \"scene\" \\ name: #1";
  c.seed = 18446744073709551615ULL;
  c.duration_s = 1.0 / 3.0;
  c.start_stamp = 1'234'567'890'123'456'789;
  c.trajectory = {.file = "/data/path with spaces/poses.txt",
                  .format = "kitti",
                  .kitti_rate_hz = 9.5,
                  .knot_spacing_s = 0.1 + 0.2,
                  .motion = sim::Motion::kHandheld};
  c.body_height_m = 1e-300;
  c.ground_truth_rate_hz = 123.456;
  c.origin = {-33.8688197, 151.2092955, -12.5};
  c.threads = 3;
  c.write_bag = true;
  const Stamp s = c.start_stamp;

  c.imu.enabled = false;
  c.imu.rate_hz = 400.5;
  c.imu.noise = {1.1e-3, 2.2e-4, 3.3e-5, 4.4e-6, {0.01, -0.02, 0.03}, {-1e-4, 2e-4, 4.9406564584124654e-324},
                 160.0,  8.7};

  c.lidar.enabled = false;
  c.lidar.model = {.model = "livox_avia",
                   .rate_hz = 12.5,
                   .horizontal_resolution_deg = 0.35,
                   .min_range_m = 0.75,
                   .max_range_m = 150.0,
                   .range_noise_std_m = 0.033,
                   .dropout_probability = 0.125};
  c.lidar.keyframe_rate_hz = 2.5;
  c.lidar.placement = {Pose(0.1, -0.2, 0.3, 0.11, -0.22, 0.33), 0.1, {1.0, -2.0, 3.0}, {0.01, 0.02, -0.03}};

  sim::CameraConfig& m = c.camera.model;
  c.camera.enabled = false;
  m.pinhole.width = 1280, m.pinhole.height = 720;
  m.pinhole.fx = 701.5, m.pinhole.fy = 702.25, m.pinhole.cx = 640.125, m.pinhole.cy = 359.75;
  m.k1 = -0.28, m.k2 = 0.07, m.p1 = 1e-4, m.p2 = -2e-4, m.k3 = 0.001;
  m.rate_hz = 30.0, m.noise_std_dn = 2.5, m.supersampling = 3;
  m.sun_direction_world = {-0.5, 0.25, 1.0 / 7.0};
  m.ambient = 0.2, m.exposure = 1.7, m.textured = false;
  m.darkness = {Window(s, 1'000'000'001, 2'500'000'000), Window(s, -500'000'000, 1)};
  m.exposure_changes = {{Window(s, 3'000'000'000, 4'000'000'000), 2.0}, {Window(s, 5, 6), 0.3}};
  m.occlusions = {Window(s, 7'123'456'789, 8'000'000'000)};
  m.passing_panels = {Window(s, 9'000'000'001, 9'500'000'000)};
  c.camera.placement = {sim::ForwardLookingCamera({0.5, -0.1, 0.2}) * Pose(0.01, 0.02, 0.03, 0, 0, 0),
                        -0.02,
                        {0.5, 0.5, -0.5},
                        {0, 0, 0.01}};
  c.camera.stereo_baseline_m = 0.12;

  c.wheel.enabled = false;
  c.wheel.model.rate_hz = 100.0;
  c.wheel.model.wheel_radius_m = 0.2;
  c.wheel.model.baseline_m = 0.6;
  c.wheel.model.radius_error = 0.01;
  c.wheel.model.baseline_error = -0.02;
  c.wheel.model.encoder_resolution_ticks = 4096;
  c.wheel.model.wheel_speed_noise_std = 0.05;
  c.wheel.model.slips = {{Window(s, 10'000'000'000, 12'000'000'000), 0.3}, {Window(s, 1, 2), -1.0}};
  c.wheel.model.floats = {Window(s, 20'000'000'000, 20'500'000'000)};
  c.wheel.placement = {Pose(0, 0, 0.5, -0.4, 0.0, -0.6), 0.005, {0, 0, 1}, {0.1, 0, 0}};

  c.gnss.enabled = false;
  c.gnss.model.rate_hz = 10.0;
  c.gnss.model.quality = GnssQuality::kRtkFloat;
  c.gnss.model.quality_changes = {{Window(s, 0, 5'000'000'000), GnssQuality::kRtkFixed},
                                  {Window(s, 6'000'000'000, 7'000'000'000), GnssQuality::kSingle}};
  c.gnss.model.outages = {Window(s, 30'000'000'000, 40'000'000'000)};
  c.gnss.model.multipath = {{Window(s, 41'000'000'000, 45'000'000'000), {3.0, -4.0, 0.5}}};
  c.gnss.model.rtk_fixed = {0.01, 0.03, 1.0};
  c.gnss.model.rtk_float = {0.2, 0.4, 8.0};
  c.gnss.model.single = {2.0, 4.0, 60.0};
  c.gnss.placement = {Pose(0, 0, 0, 0.1, 0.2, 0.9), 0.25, {0, 0, 0}, {0, 0, 0.1}};
  return c;
}

inline DatasetConfig NonDefaultDataset() {
  DatasetConfig c;
  c.reader.format = DatasetFormat::kRosBag;
  c.reader.topics = {{"/imu/data", SensorKind::kImu, std::nullopt},
                     {"/velodyne \"points\"", SensorKind::kLidar, Pose(0.1, -0.2, 0.3, 0.01, 0.02, 1.5)}};
  c.reader.imu_accel_unit = ImuAccelUnit::kStandardGravity;
  c.reader.derive_point_times_from_azimuth = false;
  c.reader.point_time_convention = AzimuthConvention{AzimuthSweep::kCounterClockwise, SweepStart::kAhead};
  c.reader.lidar_sweep_period_s = 0.05;
  c.reader.folder_scan_stamp = ScanStampPosition::kSweepStart;
  c.reader.calibration_file = "rig/calibration_estimated.yaml";
  c.stream.time_offsets = {{"lidar", -12'000'000}, {"/fix", 200'000'001}};
  c.stream.reorder_window = 2'500'000'000;
  return c;
}

inline estimator::LidarOdometryConfig NonDefaultOdometry() {
  estimator::LidarOdometryConfig c;
  c.input_voxel_m = 0.75;
  c.window_size = 6;
  c.max_iterations = 5;
  c.max_solver_time_s = 0.125;
  c.condensed_lidar_rounds = 3;
  c.max_residuals_per_scan = 900;
  c.huber_m = 1.0 / 3.0;
  c.min_range_m = 2;
  c.max_range_m = 70;
  c.map_insert_voxel_m = 0.3;
  c.association_rounds = 4;
  c.min_match_ratio = 0.4;
  c.max_speed_mps = 40;
  c.max_angular_rate_rad_s = 6.5;
  c.max_rejected_scans = 5;
  c.max_prediction_s = 0.75;
  c.min_points = 60;
  c.max_plane_distance_m = 0.8;
  c.marginalize = false;
  c.drop_weak_directions = true;
  c.motion = {3.5, 1.25, 0.6};
  c.map = {0.25, 7, 80, 0.2, 6, 0.02, 0.5, 2};
  c.imu_max_gap_s = 0.1;
  c.imu_max_wait_s = 0.75;
  c.imu_deskew = true;
  c.estimate_lidar_translation = true;
  c.lidar_translation_sigma_m = 0.03;
  c.lidar_translation_min_turn_deg = 1.5;
  c.wheel_carries_weak_translations = false;
  c.imu = {0.03, 0.002, 0.004, 2.5e-5, 9.81, 0.2, 0.02, 34.9, 156.9};
  c.init = {4, 3, 25, 0.15, 0.03, 0.4, 0.06, 0.5, 0.15, 0.3, 0.004, 0.03, 2.5};
  c.wheel = {.forward_velocity_density = 0.07,
             .yaw_rate_density = 0.02,
             .nonholonomic_velocity_density = 0.3,
             .suspension_tilt_sigma = 0.03,
             .tilt_per_acceleration = 0.02,
             .roll_pitch_rate_density = 0.15,
             .max_gap_s = 0.25,
             .time_offset_s = 0.01,
             .estimate_scale = false,
             .scale_prior_sigma = 0.03,
             .stationary_updates = false,
             .schedule = {.enabled = false,
                          .speed_tolerance_mps = 0.7,
                          .yaw_rate_tolerance_rad_s = 0.4,
                          .speed_weight = 0.6,
                          .drift_mps_per_s = 0.2,
                          .max_shut_s = 12.0,
                          .baseline_time_s = 2.0,
                          .change_window_s = 1.5,
                          .change_tolerance_mps = 0.8,
                          .threshold = 0.3,
                          .release_margin = 0.05,
                          .release_keyframes = 5}};
  c.gnss.min_status = GnssFixStatus::kRtkFloat;
  c.gnss.fix = {0.6, 1.5, 3.0, 6.0, 0.8};
  c.gnss.sbas = {0.4, 1.2, 1.5, 2.5, 0.7};
  c.gnss.rtk_float = {0.06, 1.1, 0.35, 0.6, 0.3};
  c.gnss.rtk_fixed = {0.02, 2.0, 0.04, 0.06, 0.1};
  c.gnss.offset_correlation_time_s = 45;
  c.gnss.use_nominal_for_unknown = true;
  c.gnss.integrity_gate = 11.34;
  c.gnss.prediction_sigma_m = 0.5;
  c.gnss.prediction_drift_fraction = 0.03;
  c.gnss.step_max_hold_s = 12.5;
  c.gnss.min_alignment_baseline_m = 20;
  c.gnss.min_alignment_fixes = 8;
  c.gnss.max_alignment_rms_m = 5;
  c.gnss.max_interpolation_gap_s = 0.5;
  c.gnss.max_snap_s = 0.1;
  c.visual.stereo = false;
  c.visual.pixel_sigma_px = 1.5;
  c.visual.huber_sigmas = 3;
  c.visual.min_parallax_deg = 2;
  c.visual.min_depth_m = 1;
  c.visual.max_depth_m = 80;
  c.visual.max_reprojection_px = 4;
  c.visual.hold_map_depth = false;
  c.visual.time_offset_s = -0.01;
  c.visual.estimate_time_offset = true;
  c.visual.time_offset_sigma_s = 0.02;
  c.visual.estimate_extrinsic = true;
  c.visual.extrinsic_rotation_sigma_deg = 3;
  c.visual.extrinsic_translation_sigma_m = 0.1;
  c.visual.max_iterations = 12;
  c.visual.max_solver_time_s = 0.2;
  c.visual.max_static_flow_px = 1;
  c.visual.tracker.max_features = 200;
  c.visual.tracker.min_distance_px = 20;
  c.visual.tracker.quality_level = 0.02;
  c.visual.tracker.klt_window_px = 21;
  c.visual.tracker.klt_pyramid_levels = 4;
  c.visual.tracker.max_fb_error_px = 1;
  c.visual.tracker.ransac_threshold_px = 2;
  c.visual.tracker.ransac_confidence = 0.999;
  c.visual.tracker.min_track_length = 5;
  c.visual.tracker.keyframe_parallax_px = 15;
  c.visual.tracker.grid_cells = 6;
  c.visual.tracker.min_contrast_dn = 4;
  c.visual.tracker.normalize_exposure = false;
  c.visual.tracker.smoothing_sigma_px = 1.5;
  c.visual.schedule.enabled = true;
  c.visual.schedule.tolerance_px = 5;
  c.visual.schedule.min_tracks = 15;
  c.visual.schedule.reference_tracks = 60;
  c.visual.schedule.residual_threshold_px = 3;
  c.visual.schedule.threshold = 0.6;
  c.visual.schedule.release_margin = 0.2;
  c.visual.schedule.release_frames = 4;
  c.visual.schedule.max_shut_s = 4;
  return c;
}

// The wio: keys (the parts shared with lio: from NonDefaultOdometry: every one of them differs there too).
inline estimator::InertialOdometryConfig NonDefaultWio() {
  const estimator::LidarOdometryConfig lio = NonDefaultOdometry();
  estimator::InertialOdometryConfig c;
  c.node_interval_s = 0.125;
  c.window_size = 16;
  c.init_window_nodes = 8;
  c.max_iterations = 4;
  c.max_solver_time_s = 0.03;
  c.marginalize = false;
  c.init_accel_bias_sigma = 0.05;
  c.init_gyro_bias_sigma = 0.004;
  c.imu_max_gap_s = 0.08;
  c.max_speed_mps = 30;
  c.wheel_max_wait_s = 0.25;
  c.imu = lio.imu;
  c.init = lio.init;
  // The LIO-only keys are not wio: keys.
  const estimator::InertialInitConfig defaults;
  c.init.min_scans = defaults.min_scans;
  c.init.map_settle_scans = defaults.map_settle_scans;
  c.init.max_scans = defaults.max_scans;
  c.init.max_tilt_sigma_deg = defaults.max_tilt_sigma_deg;
  c.init.lidar_position_sigma_m = defaults.lidar_position_sigma_m;
  c.init.accel_bias_sigma = defaults.accel_bias_sigma;
  c.init.max_chi2_per_dof = defaults.max_chi2_per_dof;
  c.wheel = lio.wheel;
  c.wheel.stationary_updates = true;  // off by default in WIO, on in LIO
  c.gnss = lio.gnss;
  c.visual = lio.visual;
  return c;
}

inline SplatConfig NonDefaultSplat() {
  SplatConfig c;
  splat::TrainingOptions& t = c.training;
  t.iterations = 123;
  t.sh_degree = 1;
  t.sh_degree_interval = 50;
  t.lr_position_initial = 3.25e-4;
  t.lr_position_final = 2e-6;
  t.lr_log_scale = 0.004;
  t.lr_rotation = 0.002;
  t.lr_opacity = 0.04;
  t.lr_sh_dc = 0.003;
  t.lr_sh_rest = 1e-4;
  t.adam_beta1 = 0.8;
  t.adam_beta2 = 0.99;
  t.adam_epsilon = 1e-12;
  t.ssim_weight = 0.3;
  t.depth_weight = 0.1;
  t.densify_from = 10;
  t.densify_until = 100;
  t.densify_interval = 20;
  t.densify_gradient_threshold = 3e-4;
  t.dense_fraction = 0.02;
  t.prune_opacity = 0.01;
  t.prune_world_fraction = 0.2;
  t.opacity_reset_interval = 500;
  t.max_gaussians = 12345;
  t.render.background = Eigen::Vector3f(0.25f, 0.1f, 1.0f);
  t.seed = 99;
  c.time_budget_s = 12.5;
  c.width = 200, c.height = 150;
  c.max_width = 640;
  c.coarse_to_fine_interval = 250;
  c.keyframe_distance_m = 0.7;
  c.keyframe_angle_deg = 7.5;
  c.holdout_stride = 5;
  c.comparisons = 2;
  c.seed_points = 5000;
  c.feature_seed_corners = 50;
  c.sky_gaussians = 100;
  c.mask_image = "masks/hood.png";
  c.exposure_compensation = true;
  c.exposure_from = 50;
  c.exposure_prior = 0.25;
  return c;
}

inline ConfigFile NonDefaultConfigFile() {
  ConfigFile c;
  c.dataset = NonDefaultDataset();
  c.odometry = NonDefaultOdometry();
  c.wio = NonDefaultWio();
  c.splat = NonDefaultSplat();
  c.sim = NonDefaultConfig();
  return c;
}

}  // namespace uf::app::test
