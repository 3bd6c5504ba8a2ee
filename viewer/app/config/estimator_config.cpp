// The `lo:` and `lio:` sections: their schemas (every key once, with its unit and meaning).
#include "viewer/app/config/estimator_config.h"

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

using config::Codec;
using config::Schema;
using estimator::ConstantVelocityNoise;
using estimator::LidarOdometryConfig;
using estimator::VoxelMapConfig;

Schema<LidarOdometryConfig> MakeLoSchema() {
  using C = LidarOdometryConfig;
  Schema<C> s("lo");
  s.Key("input_voxel_m", &C::input_voxel_m, "m",
        "downsampling of each scan for registration (one point per voxel, drawn at random among its points)");
  s.Key("window_size", &C::window_size, "scans", "scans in the sliding window (each has 1-2 states), >= 2");
  s.Key("max_iterations", &C::max_iterations, "LM iterations", "per solve (the dense LM solver)");
  s.Key("max_solver_time_s", &C::max_solver_time_s, "s", "wall-time budget per solve");
  s.Key("condensed_lidar_rounds", &C::condensed_lidar_rounds, "solves",
        "the window's solve takes each scan's point-to-plane factors as their Gauss-Newton model, condensed "
        "again where the scan's poses moved past 5 mm / 0.5 mrad, at most this many solves; 0: the residuals "
        "themselves at every iteration");
  s.Key("max_residuals_per_scan", &C::max_residuals_per_scan, "residuals",
        "point-to-plane residuals of one scan");
  s.Key("huber_m", &C::huber_m, "m", "robust loss scale, point-to-plane distance");
  s.Key("min_range_m", &C::min_range_m, "m", "nearer points are dropped");
  s.Key("max_range_m", &C::max_range_m, "m", "farther points are dropped");
  s.Key("map_insert_voxel_m", &C::map_insert_voxel_m, "m",
        "downsampling of the deskewed scan inserted into the map (one point per voxel, drawn at random)");
  s.Key("association_rounds", &C::association_rounds, "rounds",
        "at most this many solve + re-query rounds per scan (until the pose moves < 5 mm / 1 mrad)");
  s.Key("min_match_ratio", &C::min_match_ratio, "",
        "a registration with fewer of its points on map planes (within 2 plane sigmas) than this share of "
        "the recent scans' median is rejected");
  s.Key("max_speed_mps", &C::max_speed_mps, "m/s",
        "a registration moving faster since the last registered scan is rejected; in LIO a faster state is "
        "divergence (re-initialization)");
  s.Key("max_angular_rate_rad_s", &C::max_angular_rate_rad_s, "rad/s",
        "a registration turning faster since the last registered scan is rejected");
  s.Key("max_rejected_scans", &C::max_rejected_scans, "scans",
        "consecutive rejected registrations that restart the local map (a discontinuity in the report)");
  s.Key("max_prediction_s", &C::max_prediction_s, "s",
        "the constant-velocity guess extrapolates at most this far (the pose holds after a longer gap)");
  s.Key("min_points", &C::min_points, "points", "scans with fewer prepared points are skipped");
  s.Key("max_plane_distance_m", &C::max_plane_distance_m, "m",
        "correspondences farther from their plane are dropped");
  s.Key("marginalize", &C::marginalize, "", "oldest states into a prior (false: the oldest pose held fixed)");
  s.Key("drop_weak_directions", &C::drop_weak_directions, "",
        "a registered scan's point-to-plane factors lose their say along its weak directions (reliability "
        "scheduling; the IMU, wheel or motion prior carry them)");

  Schema<ConstantVelocityNoise> motion;
  motion.Key("acc_density", &ConstantVelocityNoise::acc_density, "m/s^2/sqrt(Hz)",
             "constant-velocity prior between consecutive poses: white-noise linear acceleration");
  motion.Key("angular_acc_density", &ConstantVelocityNoise::angular_acc_density, "rad/s^2/sqrt(Hz)",
             "constant-velocity prior: white-noise angular acceleration");
  motion.Key("sweep_acc_density", &ConstantVelocityNoise::sweep_acc_density, "m/s^2/sqrt(Hz)",
             "sweep-velocity prior of LO on scans kept apart (keyframes): white-noise world-frame "
             "acceleration between the last scan interval and the sweep; 0: off");
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
  map.Key("neighbour_weight", &VoxelMapConfig::neighbour_weight, "",
          "where a voxel's plane passes: the centroid of its 3x3x3 block with a neighbour's points weighted "
          "per axis of offset (face w, edge w^2, corner w^3; 1: the block's plain centroid)");
  map.Key(
      "min_plane_rings", &VoxelMapConfig::min_plane_rings, "rings",
      "distinct LiDAR rings needed in the 3x3x3 block for a plane (1: off; 0: auto, 2 for a LiDAR of "
      "32 rings or more, else 1; applies where rings are known; 2 suits a sparser LiDAR outdoors too, not "
      "indoors)");
  s.Nest("map", &C::map, map);
  return s;
}

Schema<LidarOdometryConfig> MakeLioSchema() {
  using C = LidarOdometryConfig;
  Schema<C> s("lio");
  s.Key("imu_deskew", &C::imu_deskew, "",
        "correct each sweep's points by the IMU's motion within the sweep beyond constant velocity");
  s.Key("estimate_lidar_translation", &C::estimate_lidar_translation, "",
        "estimate the LiDAR extrinsic's translation in the window (off: held as given)");
  s.Key("lidar_translation_sigma_m", &C::lidar_translation_sigma_m, "m",
        "prior of the estimated translation about the given one");
  s.Key("lidar_translation_min_turn_deg", &C::lidar_translation_min_turn_deg, "deg",
        "the translation moves only while the window's orientations spread this much about every axis");
  s.Key("imu_max_gap_s", &C::imu_max_gap_s, "s",
        "a longer step between IMU samples is a gap, bridged by the constant-velocity prior");
  s.Key("imu_max_wait_s", &C::imu_max_wait_s, "s (stream time)",
        "how long a scan waits for the IMU to cover it");
  s.Nest("imu", &C::imu,
         config::ImuNoiseSchema("10x the ADIS16448 datasheet: a margin for the budgeted solves"));
  s.Nest("init", &C::init, config::InitSchema(true));
  s.Key("wheel_carries_weak_translations", &C::wheel_carries_weak_translations, "",
        "LWIO: a scan's point-to-plane factors lose their say along the translations it pins weakly and "
        "less than the wheel does over its interval (reliability scheduling)");
  s.Nest("wheel", &C::wheel, config::WheelSchema());
  s.Nest("gnss", &C::gnss, config::GnssSchema());
  s.Nest("visual", &C::visual, config::VisualSchema());
  return s;
}

}  // namespace

std::string EmitLidarOdometryConfig(const LidarOdometryConfig& config) {
  std::string text = config::EmitSection(config::LoSchema(), config);
  // lio: holds the wheel keys too, which an LO run with wheel factors (lwo) reads.
  if (config.use_imu || config.use_wheel) text += config::EmitSection(config::LioSchema(), config);
  return text;
}

namespace config {

const Schema<LidarOdometryConfig>& LoSchema() { return BuiltOnce<MakeLoSchema>(); }

const Schema<LidarOdometryConfig>& LioSchema() { return BuiltOnce<MakeLioSchema>(); }

}  // namespace config
}  // namespace uf::app
