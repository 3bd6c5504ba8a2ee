// The `wio:` section: its schema (every key once, with its unit and meaning).
#include "viewer/app/config/wio_config.h"

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

using config::Schema;
using estimator::InertialOdometryConfig;

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
  return s;
}

Schema<estimator::VisualFactorConfig> VisualSchema() {
  using V = estimator::VisualFactorConfig;
  Schema<V> s;
  s.Key("pixel_sigma_px", &V::pixel_sigma_px, "px", "reprojection noise (vio, vwio)");
  s.Key("huber_sigmas", &V::huber_sigmas, "sigmas", "Huber loss of a reprojection: linear beyond this");
  s.Key("min_parallax_deg", &V::min_parallax_deg, "deg", "a landmark's rays must span this angle");
  s.Key("min_depth_m", &V::min_depth_m, "m", "a landmark lies at least this far in front of every camera");
  s.Key("max_depth_m", &V::max_depth_m, "m", "and at most this far from its anchor camera");
  s.Key("max_reprojection_px", &V::max_reprojection_px, "px",
        "after a solve, a landmark reprojecting worse than this anywhere is dropped");
  s.Key("time_offset_s", &V::time_offset_s, "s",
        "camera time offset t_d to start from (camera stamp + t_d = IMU time)");
  s.Key("estimate_time_offset", &V::estimate_time_offset, "", "estimate t_d in the window");
  s.Key("time_offset_sigma_s", &V::time_offset_sigma_s, "s",
        "prior of the estimated t_d about its start value");
  s.Key("max_iterations", &V::max_iterations, "LM iterations",
        "per solve with the camera (in place of wio.max_iterations)");
  s.Key("max_solver_time_s", &V::max_solver_time_s, "s",
        "wall-time budget per solve with the camera (in place of wio.max_solver_time_s)");
  s.Key("max_static_flow_px", &V::max_static_flow_px, "px per frame",
        "vio's static start: the tracked features' mean motion must stay below this (the camera is still)");
  s.Nest("tracker", &V::tracker, TrackerSchema());
  return s;
}

Schema<InertialOdometryConfig> MakeWioSchema() {
  using C = InertialOdometryConfig;
  Schema<C> s("wio");
  s.Key("node_interval_s", &C::node_interval_s, "s", "a node every this much IMU time");
  s.Key("window_size", &C::window_size, "nodes", "nodes in the sliding window, >= init_window_nodes");
  s.Key("init_window_nodes", &C::init_window_nodes, "nodes",
        "the inertial initialization waits for this many node stamps, >= 3");
  s.Key("max_iterations", &C::max_iterations, "LM iterations", "per solve (one solve per node)");
  s.Key("max_solver_time_s", &C::max_solver_time_s, "s", "wall-time budget per solve");
  s.Key("marginalize", &C::marginalize, "", "oldest nodes into a prior (false: dropped with their factors)");
  s.Key("init_accel_bias_sigma", &C::init_accel_bias_sigma, "m/s^2",
        "prior of the accelerometer bias about the initialization's estimate (a MEMS turn-on bias)");
  s.Key("init_gyro_bias_sigma", &C::init_gyro_bias_sigma, "rad/s",
        "prior of the gyro bias about the initialization's estimate");
  s.Key("imu_max_gap_s", &C::imu_max_gap_s, "s",
        "a longer step between IMU samples is a gap: the window ends and starts again after it");
  s.Key("max_speed_mps", &C::max_speed_mps, "m/s", "a faster state is divergence (re-initialization)");
  s.Key("wheel_max_wait_s", &C::wheel_max_wait_s, "s (IMU time)",
        "a node waits this long for the wheel to cover it, then goes ahead without its wheel factor");
  s.Nest("imu", &C::imu, config::ImuNoiseSchema("2x the ADIS16448 datasheet"));
  s.Nest("init", &C::init, config::InitSchema(false));
  s.Nest("wheel", &C::wheel, config::WheelSchema());
  s.Nest("gnss", &C::gnss, config::GnssSchema());
  s.Nest("visual", &C::visual, VisualSchema());
  return s;
}

}  // namespace

std::string EmitInertialOdometryConfig(const InertialOdometryConfig& config) {
  return config::EmitSection(config::WioSchema(), config);
}

namespace config {

const Schema<InertialOdometryConfig>& WioSchema() { return BuiltOnce<MakeWioSchema>(); }

}  // namespace config
}  // namespace uf::app
