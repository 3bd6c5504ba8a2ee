// The `wio:` section: its schema (every key once, with its unit and meaning).
#include "viewer/app/config/wio_config.h"

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

using config::Schema;
using estimator::InertialOdometryConfig;

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
  s.Nest("visual", &C::visual, config::VisualSchema());
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
