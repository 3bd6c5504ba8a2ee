// The `lo:` and `lio:` sections: their schemas (every key once, with its unit and meaning).
#include "viewer/app/config/estimator_config.h"

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

using config::Codec;
using config::Schema;
using estimator::ConstantVelocityNoise;
using estimator::GnssFactorConfig;
using estimator::ImuNoiseParams;
using estimator::InertialInitConfig;
using estimator::LidarOdometryConfig;
using estimator::VoxelMapConfig;

Schema<LidarOdometryConfig> MakeLoSchema() {
  using C = LidarOdometryConfig;
  Schema<C> s("lo");
  s.Key("input_voxel_m", &C::input_voxel_m, "m", "downsampling of each scan for registration");
  s.Key("window_size", &C::window_size, "scans", "scans in the sliding window (each has 1-2 states), >= 2");
  s.Key("max_iterations", &C::max_iterations, "LM iterations", "per solve (the dense LM solver)");
  s.Key("max_solver_time_s", &C::max_solver_time_s, "s", "wall-time budget per solve");
  s.Key("max_residuals_per_scan", &C::max_residuals_per_scan, "residuals",
        "point-to-plane residuals of one scan");
  s.Key("huber_m", &C::huber_m, "m", "robust loss scale, point-to-plane distance");
  s.Key("min_range_m", &C::min_range_m, "m", "nearer points are dropped");
  s.Key("max_range_m", &C::max_range_m, "m", "farther points are dropped");
  s.Key("map_insert_voxel_m", &C::map_insert_voxel_m, "m",
        "downsampling of the deskewed scan inserted into the map");
  s.Key("association_rounds", &C::association_rounds, "rounds",
        "at most this many solve + re-query rounds per scan (until the pose moves < 5 mm / 1 mrad)");
  s.Key("max_correction_m", &C::max_correction_m, "m",
        "a solve moving a scan farther from its guess diverged");
  s.Key("max_correction_rad", &C::max_correction_rad, "rad", "a solve rotating a scan more diverged");
  s.Key("min_points", &C::min_points, "points", "scans with fewer prepared points are skipped");
  s.Key("max_plane_distance_m", &C::max_plane_distance_m, "m",
        "correspondences farther from their plane are dropped");
  s.Key("marginalize", &C::marginalize, "", "oldest states into a prior (false: the oldest pose held fixed)");

  Schema<ConstantVelocityNoise> motion;
  motion.Key("acc_density", &ConstantVelocityNoise::acc_density, "m/s^2/sqrt(Hz)",
             "constant-velocity prior between consecutive poses: white-noise linear acceleration");
  motion.Key("angular_acc_density", &ConstantVelocityNoise::angular_acc_density, "rad/s^2/sqrt(Hz)",
             "constant-velocity prior: white-noise angular acceleration");
  s.Nest("motion", &C::motion, motion);

  Schema<VoxelMapConfig> map;
  map.Key("voxel_m", &VoxelMapConfig::voxel_m, "m", "voxel edge of the local map");
  map.Key("max_points_per_voxel", &VoxelMapConfig::max_points_per_voxel, "points", "points kept per voxel");
  map.Key("max_range_m", &VoxelMapConfig::max_range_m, "m",
          "voxels farther from the scan's end position are dropped");
  map.Key("plane_eigen_ratio", &VoxelMapConfig::plane_eigen_ratio, "", "plane gate lambda_min / lambda_mid");
  map.Key("min_plane_points", &VoxelMapConfig::min_plane_points, "points",
          "points needed in the 3x3x3 block for a plane");
  map.Key("min_plane_sigma_m", &VoxelMapConfig::min_plane_sigma_m, "m", "floor of a plane's sigma");
  s.Nest("map", &C::map, map);
  return s;
}

Schema<estimator::GnssStatusNoise> GnssNoiseSchema(const std::string& status) {
  using N = estimator::GnssStatusNoise;
  Schema<N> s;
  s.Key("min_sigma_m", &N::min_sigma_m, "m", status + " fixes: floor of the sigma along every axis");
  s.Key("sigma_scale", &N::sigma_scale, "", "k >= 1: the reported covariance is multiplied by k^2");
  s.Key("nominal_horizontal_sigma_m", &N::nominal_horizontal_sigma_m, "m",
        "per horizontal axis, for an unknown (all-zero) covariance with use_nominal_for_unknown");
  s.Key("nominal_vertical_sigma_m", &N::nominal_vertical_sigma_m, "m", "likewise, up");
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

Schema<GnssFactorConfig> GnssSchema() {
  using G = GnssFactorConfig;
  Schema<G> s;
  s.Key("min_status", &G::min_status, FixStatusCodec(), "",
        "GNSS factor (lio+g, lwgio): fixes of a lower status are not used (fix < sbas < rtk_float < "
        "rtk_fixed)");
  s.Key("use_nominal_for_unknown", &G::use_nominal_for_unknown, "",
        "use the status' nominal sigmas for a fix with an all-zero covariance (false: skip it)");
  s.Key("integrity_gate", &G::integrity_gate, "chi-square, 3 dof",
        "a fix whose squared Mahalanobis innovation exceeds this is rejected (16.27: 99.9 %)");
  s.Key("prediction_sigma_m", &G::prediction_sigma_m, "m",
        "uncertainty of the predicted antenna position in the innovation test");
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

Schema<LidarOdometryConfig> MakeLioSchema() {
  using C = LidarOdometryConfig;
  Schema<C> s("lio");
  s.Key("imu_max_gap_s", &C::imu_max_gap_s, "s",
        "a longer step between IMU samples is a gap, bridged by the constant-velocity prior");
  s.Key("imu_max_wait_s", &C::imu_max_wait_s, "s (stream time)",
        "how long a scan waits for the IMU to cover it");
  s.Key("max_speed_mps", &C::max_speed_mps, "m/s", "a faster state is divergence (re-initialization)");

  Schema<ImuNoiseParams> imu;
  imu.Key("accel_noise_density", &ImuNoiseParams::accel_noise_density, "m/s^2/sqrt(Hz)",
          "accelerometer white noise (10x the ADIS16448 datasheet: a margin for the budgeted solves)");
  imu.Key("gyro_noise_density", &ImuNoiseParams::gyro_noise_density, "rad/s/sqrt(Hz)",
          "gyroscope white noise (10x the datasheet)");
  imu.Key("accel_bias_random_walk", &ImuNoiseParams::accel_bias_random_walk, "m/s^3/sqrt(Hz)",
          "accelerometer bias random walk");
  imu.Key("gyro_bias_random_walk", &ImuNoiseParams::gyro_bias_random_walk, "rad/s^2/sqrt(Hz)",
          "gyroscope bias random walk");
  imu.Key("gravity", &ImuNoiseParams::gravity, "m/s^2", "g_world = (0, 0, -gravity)");
  imu.Key("max_accel_bias_change", &ImuNoiseParams::max_accel_bias_change, "m/s^2",
          "first-order bias update of the preintegration up to this, then re-integration");
  imu.Key("max_gyro_bias_change", &ImuNoiseParams::max_gyro_bias_change, "rad/s",
          "likewise for the gyro bias");
  s.Nest("imu", &C::imu, imu);

  Schema<InertialInitConfig> init;
  init.Key("window_scans", &InertialInitConfig::window_scans, "scans",
           "scans solved as LO before the IMU alignment is tried, >= 3 and < lo.window_size");
  init.Key("static_max_gyro_std", &InertialInitConfig::static_max_gyro_std, "rad/s",
           "static initialization: spread of the angular rate at rest");
  init.Key("static_max_acc_std", &InertialInitConfig::static_max_acc_std, "m/s^2",
           "static initialization: spread of the specific force at rest");
  init.Key("static_max_motion_m", &InertialInitConfig::static_max_motion_m, "m",
           "static initialization: the LO poses may move this much at rest");
  init.Key("max_gravity_error", &InertialInitConfig::max_gravity_error, "fraction of gravity",
           "LiDAR-aided initialization is admitted when abs(|g| - gravity) <= this * gravity");
  s.Nest("init", &C::init, init);

  using estimator::WheelFactorConfig;
  using W = WheelFactorConfig;
  Schema<W> wheel;
  wheel.Key("forward_velocity_density", &W::forward_velocity_density, "m/s/sqrt(Hz)",
            "wheel factor (lwio, lwgio): white noise of the forward speed");
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
  s.Nest("wheel", &C::wheel, wheel);
  s.Nest("gnss", &C::gnss, GnssSchema());
  return s;
}

}  // namespace

std::string EmitLidarOdometryConfig(const LidarOdometryConfig& config) {
  std::string text = config::EmitSection(config::LoSchema(), config);
  if (config.use_imu) text += config::EmitSection(config::LioSchema(), config);
  return text;
}

namespace config {

const Schema<LidarOdometryConfig>& LoSchema() { return BuiltOnce<MakeLoSchema>(); }

const Schema<LidarOdometryConfig>& LioSchema() { return BuiltOnce<MakeLioSchema>(); }

}  // namespace config
}  // namespace uf::app
