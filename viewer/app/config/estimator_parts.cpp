// The parts of the estimator sections that more than one section holds: the IMU noise, the inertial
// initialization, the wheel and the GNSS factors (lio: and wio:).
#include "viewer/app/config/section_schemas.h"

namespace uf::app::config {
namespace {

using estimator::GnssFactorConfig;
using estimator::ImuNoiseParams;
using estimator::InertialInitConfig;
using estimator::WheelFactorConfig;
using estimator::WheelScheduleConfig;

Schema<estimator::GnssStatusNoise> GnssNoiseSchema(const std::string& status) {
  using N = estimator::GnssStatusNoise;
  Schema<N> s;
  s.Key("min_sigma_m", &N::min_sigma_m, "m", status + " fixes: floor of the sigma along every axis");
  s.Key("sigma_scale", &N::sigma_scale, "", "k >= 1: the reported covariance is multiplied by k^2");
  s.Key("nominal_horizontal_sigma_m", &N::nominal_horizontal_sigma_m, "m",
        "per horizontal axis, for an unknown (all-zero) covariance with use_nominal_for_unknown");
  s.Key("nominal_vertical_sigma_m", &N::nominal_vertical_sigma_m, "m", "likewise, up");
  s.Key("offset_share", &N::offset_share, "",
        "in [0, 1): share of the covariance that is a slowly varying offset, estimated per node (0: white)");
  return s;
}

Codec<GnssFixStatus> FixStatusCodec() {
  return config::NamedCodec<GnssFixStatus>(
      [](const std::string& name) -> Expected<GnssFixStatus> {
        for (GnssFixStatus status : {GnssFixStatus::kNoFix, GnssFixStatus::kFix, GnssFixStatus::kSbas,
                                     GnssFixStatus::kRtkFloat, GnssFixStatus::kRtkFixed})
          if (name == estimator::GnssStatusName(status)) return status;
        return Status::Error("unknown fix status '" + name + "' (fix, sbas, rtk_float, rtk_fixed)");
      },
      [](GnssFixStatus status) { return std::string(estimator::GnssStatusName(status)); });
}

}  // namespace

Schema<ImuNoiseParams> ImuNoiseSchema(const std::string& scale) {
  Schema<ImuNoiseParams> imu;
  imu.Key("accel_noise_density", &ImuNoiseParams::accel_noise_density, "m/s^2/sqrt(Hz)",
          "accelerometer white noise (" + scale + ")");
  imu.Key("gyro_noise_density", &ImuNoiseParams::gyro_noise_density, "rad/s/sqrt(Hz)",
          "gyroscope white noise (" + scale + ")");
  imu.Key("accel_bias_random_walk", &ImuNoiseParams::accel_bias_random_walk, "m/s^3/sqrt(Hz)",
          "accelerometer bias random walk");
  imu.Key("gyro_bias_random_walk", &ImuNoiseParams::gyro_bias_random_walk, "rad/s^2/sqrt(Hz)",
          "gyroscope bias random walk");
  imu.Key("gravity", &ImuNoiseParams::gravity, "m/s^2", "g_world = (0, 0, -gravity)");
  imu.Key("max_accel_bias_change", &ImuNoiseParams::max_accel_bias_change, "m/s^2",
          "first-order bias update of the preintegration up to this, then re-integration");
  imu.Key("max_gyro_bias_change", &ImuNoiseParams::max_gyro_bias_change, "rad/s",
          "likewise for the gyro bias");
  imu.Key("gyro_range", &ImuNoiseParams::gyro_range, "rad/s",
          "the gyroscope's full scale per axis (datasheet); a reading there is clipped and its step's noise "
          "inflated; 0: not known, not checked");
  imu.Key("accel_range", &ImuNoiseParams::accel_range, "m/s^2",
          "the accelerometer's full scale per axis, likewise");
  return imu;
}

Schema<InertialInitConfig> InitSchema(bool lidar) {
  using I = InertialInitConfig;
  Schema<I> init;
  if (lidar)
    init.Key("min_scans", &I::min_scans, "scans",
             "LiDAR-aided initialization (M) needs this many registered scans in its window, >= 3 and < "
             "lo.window_size");
  if (lidar)
    init.Key("map_settle_scans", &I::map_settle_scans, "scans",
             "M leaves out a local map's first scans (registered before its first sweep could be deskewed), "
             "in [0, 20]");
  if (lidar)
    init.Key(
        "max_scans", &I::max_scans, "scans",
        "the initialization window holds at most this many scans (older ones after they left the odometry "
        "window), in [min_scans, 200]");
  init.Key("static_min_duration_s", &I::static_min_duration_s, "s",
           "static initialization (S) needs the IMU at rest for at least this long");
  init.Key("static_max_gyro_std", &I::static_max_gyro_std, "rad/s",
           "static initialization: spread of the angular rate at rest");
  init.Key("static_max_acc_std", &I::static_max_acc_std, "m/s^2",
           "static initialization: spread of the specific force at rest");
  init.Key("static_max_vibration_deg", &I::static_max_vibration_deg, "deg",
           "static initialization: a spread above its limit is vibration at rest when the body turns by at "
           "most this (and gains at most static_max_speed_mps) over the window");
  init.Key(
      "static_max_speed_mps", &I::static_max_speed_mps, "m/s",
      lidar ? "static initialization: the LO speed beyond 3 sigma of its noise is at most this (S sets v = 0)"
            : "static initialization: the wheel moves at most this fast (S sets v = 0)");
  init.Key(
      "max_gravity_error", &I::max_gravity_error, "fraction of gravity",
      lidar ? "S and M are admitted when abs(|g| - gravity) <= this * gravity"
            : "static and wheel-aided initialization are admitted when abs(|g| - gravity) <= this * gravity");
  if (!lidar) return init;
  init.Key("max_tilt_sigma_deg", &I::max_tilt_sigma_deg, "deg",
           "M is admitted once the predicted standard deviation of its gravity direction is this small and "
           "the newest scan moved that direction by no more");
  init.Key(
      "lidar_position_sigma_m", &I::lidar_position_sigma_m, "m",
      "least noise of an LO scan position (S's speed test, M; M takes more where its residuals show it)");
  init.Key("accel_bias_sigma", &I::accel_bias_sigma, "m/s^2", "M: prior on the accelerometer bias, about 0");
  init.Key("max_chi2_per_dof", &I::max_chi2_per_dof, "-",
           "admission check: the IMU's velocity changes against the admitted state, whitened, chi-square per "
           "dof");
  return init;
}

Schema<WheelScheduleConfig> WheelScheduleSchema() {
  using S = WheelScheduleConfig;
  Schema<S> s;
  s.Key("enabled", &S::enabled, "",
        "score each interval's wheel motion against the IMU's prediction and leave its factor out while "
        "they disagree (reliability scheduling)");
  s.Key("speed_tolerance_mps", &S::speed_tolerance_mps, "m/s",
        "speed disagreement that saturates the score's speed term");
  s.Key("yaw_rate_tolerance_rad_s", &S::yaw_rate_tolerance_rad_s, "rad/s",
        "yaw-rate disagreement that saturates its yaw term");
  s.Key("speed_weight", &S::speed_weight, "", "weight of the speed term (the yaw term has 1 - this)");
  s.Key("drift_mps_per_s", &S::drift_mps_per_s, "m/s per s",
        "while the wheel is out the speed tolerance grows by this per second (the IMU's prediction drifts)");
  s.Key("change_window_s", &S::change_window_s, "s",
        "the wheel's speed change against the IMU's over this long also counts (a fault that builds up "
        "slowly; 0: off); and the wheel joins unscored for this long after the inertial initialization and "
        "after a clipped IMU interval");
  s.Key("change_tolerance_mps", &S::change_tolerance_mps, "m/s",
        "the disagreement of those speed changes that saturates the speed term");
  s.Key(
      "max_shut_s", &S::max_shut_s, "s",
      "after this long left out the wheel is taken back whatever its score (its disagreement the new level)");
  s.Key("baseline_time_s", &S::baseline_time_s, "s",
        "the speed disagreement of the admitted intervals, averaged over this long, is taken as the "
        "window's own velocity error (0: none)");
  s.Key("threshold", &S::threshold, "", "the wheel factor is left out at a score above this");
  s.Key("release_margin", &S::release_margin, "",
        "and admitted again once the score is at most threshold - this ...");
  s.Key("release_keyframes", &S::release_keyframes, "intervals", "... over this many intervals in a row");
  return s;
}

Schema<WheelFactorConfig> WheelSchema() {
  using W = WheelFactorConfig;
  Schema<W> wheel;
  wheel.Key("forward_velocity_density", &W::forward_velocity_density, "m/s/sqrt(Hz)",
            "wheel factor (lwio, lwgio, wio, wgio): white noise of the forward speed");
  wheel.Key("yaw_rate_density", &W::yaw_rate_density, "rad/s/sqrt(Hz)", "white noise of the yaw rate");
  wheel.Key("nonholonomic_velocity_density", &W::nonholonomic_velocity_density, "m/s/sqrt(Hz)",
            "soft non-holonomic constraint on the lateral and vertical velocity, at any speed");
  wheel.Key("suspension_tilt_sigma", &W::suspension_tilt_sigma, "rad",
            "RMS roll and pitch of the body on its suspension: lateral and vertical noise grows with speed");
  wheel.Key("tilt_per_acceleration", &W::tilt_per_acceleration, "rad/(m/s^2)",
            "lean in turns and squat under acceleration, per m/s^2: lateral and vertical noise");
  wheel.Key("roll_pitch_rate_density", &W::roll_pitch_rate_density, "rad/s/sqrt(Hz)",
            "soft constraint on the roll and pitch rates");
  wheel.Key("max_gap_s", &W::max_gap_s, "s",
            "a longer step between wheel samples leaves the interval without a factor");
  wheel.Key("time_offset_s", &W::time_offset_s, "s", "added to the wheel stamps (fixed, |.| <= 1)");
  wheel.Key("estimate_scale", &W::estimate_scale, "", "estimate the wheel scale (false: held at 1)");
  wheel.Key("scale_prior_sigma", &W::scale_prior_sigma, "", "prior of the wheel scale, relative to 1");
  wheel.Key("stationary_updates", &W::stationary_updates, "",
            "hold the nodes of an interval whose wheel samples all read no motion at one pose, at zero "
            "velocity (false: wheels that stand while the vehicle moves)");
  wheel.Nest("schedule", &W::schedule, WheelScheduleSchema());
  return wheel;
}

Schema<GnssFactorConfig> GnssSchema() {
  using G = GnssFactorConfig;
  Schema<G> s;
  s.Key("min_status", &G::min_status, FixStatusCodec(), "",
        "GNSS factor (lio+g, lwgio, wgio): fixes of a lower status are not used (fix < sbas < rtk_float < "
        "rtk_fixed)");
  s.Key("use_nominal_for_unknown", &G::use_nominal_for_unknown, "",
        "use the status' nominal sigmas for a fix with an all-zero covariance (false: skip it)");
  s.Key("integrity_gate", &G::integrity_gate, "chi-square, 3 dof",
        "a fix whose squared Mahalanobis innovation exceeds this is rejected (16.27: 99.9 %)");
  s.Key("prediction_sigma_m", &G::prediction_sigma_m, "m",
        "uncertainty of the predicted antenna position in the innovation test, right after an accepted fix");
  s.Key("prediction_drift_fraction", &G::prediction_drift_fraction, "",
        "and its growth per distance moved since (odometry drift, the alignment's yaw error)");
  s.Key("offset_correlation_time_s", &G::offset_correlation_time_s, "s",
        "correlation time of the receiver's offset (Gauss-Markov), for statuses with an offset_share");
  s.Key("step_max_hold_s", &G::step_max_hold_s, "s",
        "a fix whose innovation steps from the previous fix's (multipath) is held out with the next ones "
        "until one is back at the level before the step, at most this long; 0: each fix tested alone");
  s.Key("min_alignment_baseline_m", &G::min_alignment_baseline_m, "m",
        "the ENU alignment starts once the antenna moved this far horizontally");
  s.Key("min_alignment_fixes", &G::min_alignment_fixes, "fixes", "and over at least this many fixes");
  s.Key("max_alignment_rms_m", &G::max_alignment_rms_m, "m",
        "an alignment start with a larger residual RMS is refused (the pairs are collected again)");
  s.Key("max_interpolation_gap_s", &G::max_interpolation_gap_s, "s",
        "a fix is interpolated between nodes at most this far apart");
  s.Key("max_snap_s", &G::max_snap_s, "s",
        "else it is attached to the nearest node within this, or not used");
  for (const auto& [status, noise] :
       {std::pair{"fix", &G::fix}, std::pair{"sbas", &G::sbas}, std::pair{"rtk_float", &G::rtk_float},
        std::pair{"rtk_fixed", &G::rtk_fixed}})
    s.Nest(status, noise, GnssNoiseSchema(status));
  return s;
}

namespace {

Schema<estimator::FeatureTrackerConfig> TrackerSchema() {
  using T = estimator::FeatureTrackerConfig;
  Schema<T> s;
  s.Key("max_features", &T::max_features, "", "corners kept per frame (the paper's 150)");
  s.Key("min_distance_px", &T::min_distance_px, "px", "between features (the paper's 30)");
  s.Key("quality_level", &T::quality_level, "",
        "Shi-Tomasi: relative to the frame's strongest corner, (0, 1)");
  s.Key("klt_window_px", &T::klt_window_px, "px", "side of the Lucas-Kanade window, odd, >= 5");
  s.Key("klt_pyramid_levels", &T::klt_pyramid_levels, "", "pyramid levels above the full resolution, [0, 8]");
  s.Key("max_fb_error_px", &T::max_fb_error_px, "px",
        "forward-backward check: a track tracked back lands this close");
  s.Key("ransac_threshold_px", &T::ransac_threshold_px, "px",
        "epipolar distance of a fundamental-matrix inlier");
  s.Key("ransac_confidence", &T::ransac_confidence, "", "of the fundamental-matrix RANSAC, (0, 1)");
  s.Key("min_track_length", &T::min_track_length, "frames",
        "nodes that see a feature before it becomes a landmark");
  s.Key("keyframe_parallax_px", &T::keyframe_parallax_px, "px",
        "the front end's keyframe parallax (statistics)");
  s.Key("grid_cells", &T::grid_cells, "", "occupancy grid of the statistics: cells per side, [1, 64]");
  s.Key("min_contrast_dn", &T::min_contrast_dn, "DN", "intensity spread below which a frame is textureless");
  s.Key("normalize_exposure", &T::normalize_exposure, "",
        "map every frame to one mean and spread before tracking");
  s.Key("smoothing_sigma_px", &T::smoothing_sigma_px, "px",
        "Gaussian smoothing of every frame before corners and tracking (0: none), [0, 5]");
  return s;
}

Schema<estimator::VisualScheduleConfig> VisualScheduleSchema() {
  using S = estimator::VisualScheduleConfig;
  Schema<S> s;
  s.Key("enabled", &S::enabled, "",
        "leave a frame out while its tracks disagree with the window's predicted motion (reliability "
        "scheduling; the frames are scored either way)");
  s.Key("tolerance_px", &S::tolerance_px, "px", "a track agrees with the predicted motion within this");
  s.Key("min_tracks", &S::min_tracks, "tracks", "fewer agreeing tracks than this scores the frame 1");
  s.Key("reference_tracks", &S::reference_tracks, "tracks", "this many agreeing tracks or more adds nothing");
  s.Key("residual_threshold_px", &S::residual_threshold_px, "px",
        "the checked tracks' median error saturating the score's residual term");
  s.Key("threshold", &S::threshold, "", "the frame is left out at a score above this");
  s.Key("release_margin", &S::release_margin, "",
        "and frames are admitted again once the score is at most threshold - this ...");
  s.Key("release_frames", &S::release_frames, "frames", "... over this many frames in a row");
  s.Key("max_shut_s", &S::max_shut_s, "s", "after this long left out the frames are taken again");
  return s;
}

}  // namespace

Schema<estimator::VisualFactorConfig> VisualSchema() {
  using V = estimator::VisualFactorConfig;
  Schema<V> s;
  s.Key("stereo", &V::stereo, "",
        "with a second camera and its extrinsic in the data: stereo matches as factors and first depths");
  s.Key("pixel_sigma_px", &V::pixel_sigma_px, "px", "reprojection noise");
  s.Key("huber_sigmas", &V::huber_sigmas, "sigmas", "Huber loss of a reprojection: linear beyond this");
  s.Key("min_parallax_deg", &V::min_parallax_deg, "deg", "a landmark's rays must span this angle");
  s.Key("min_depth_m", &V::min_depth_m, "m", "a landmark lies at least this far in front of every camera");
  s.Key("max_depth_m", &V::max_depth_m, "m", "and at most this far from its anchor camera");
  s.Key("max_reprojection_px", &V::max_reprojection_px, "px",
        "after a solve, a landmark reprojecting worse than this anywhere is dropped");
  s.Key("hold_map_depth", &V::hold_map_depth, "",
        "lvio: a landmark that took its depth from the LiDAR map stays on the map's plane there");
  s.Key("time_offset_s", &V::time_offset_s, "s",
        "camera time offset t_d to start from (camera stamp + t_d = IMU time)");
  s.Key("estimate_time_offset", &V::estimate_time_offset, "", "estimate t_d in the window");
  s.Key("time_offset_sigma_s", &V::time_offset_sigma_s, "s",
        "prior of the estimated t_d about its start value");
  s.Key("estimate_extrinsic", &V::estimate_extrinsic, "",
        "estimate the camera extrinsic T_imu_cam in the window");
  s.Key("extrinsic_rotation_sigma_deg", &V::extrinsic_rotation_sigma_deg, "deg",
        "prior of the estimated extrinsic's rotation about the given one");
  s.Key("extrinsic_translation_sigma_m", &V::extrinsic_translation_sigma_m, "m",
        "prior of the estimated extrinsic's translation about the given one");
  s.Key("max_iterations", &V::max_iterations, "LM iterations",
        "per window solve with the camera (in place of the window's max_iterations)");
  s.Key("max_solver_time_s", &V::max_solver_time_s, "s",
        "wall-time budget per window solve with the camera (in place of the window's max_solver_time_s)");
  s.Key("max_static_flow_px", &V::max_static_flow_px, "px per frame",
        "vio's static start: the tracked features' mean motion below this (else the visual-inertial start)");
  s.Nest("tracker", &V::tracker, TrackerSchema());
  s.Nest("schedule", &V::schedule, VisualScheduleSchema());
  return s;
}

}  // namespace uf::app::config
