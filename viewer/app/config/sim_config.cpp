// The `sim:` section: its schema (every key once, with its unit and meaning) and the text of
// sim_config.yaml.
#include "viewer/app/config/sim_config.h"

#include "viewer/app/config/section_schemas.h"
#include "viewer/app/config/sim_config_values.h"

namespace uf::app {
namespace {

using config::Codec;
using config::KeyPath;
using config::Schema;
using config::ValueText;
using sim::SimulationConfig;
using sim::TimeWindow;

Codec<sim::GnssQuality> QualityCodec() {
  return config::NamedCodec<sim::GnssQuality>(
      [](const std::string& name) { return ParseGnssQuality(name); },
      [](sim::GnssQuality quality) { return std::string(GnssQualityName(quality)); });
}

// Windows of the part `access` gives, relative to the root's start_time_s.
template <typename Access>
void Windows(Schema<SimulationConfig>& s, std::string path, Access access, std::string doc) {
  s.Custom(
      std::move(path),
      [access](const KeyPath& at, const YAML::Node& node, SimulationConfig& c) {
        return config::ReadWindows(at, node, c.start_stamp, std::invoke(access, c));
      },
      [access](const SimulationConfig& c) {
        return ValueText{config::FormatWindows(std::invoke(access, c), c.start_stamp)};
      },
      "s from the start", std::move(doc));
}

// Events {window, KEY: value} of the part `access` gives, windows relative to the root's start_time_s.
template <typename T, typename Access>
void Events(Schema<SimulationConfig>& s, std::string path, Access access, std::string key, Codec<T> codec,
            std::string doc) {
  s.Custom(
      std::move(path),
      [access, key, codec](const KeyPath& at, const YAML::Node& node, SimulationConfig& c) {
        return config::ReadEvents(at, node, c.start_stamp, key, codec, std::invoke(access, c));
      },
      [access, key, codec](const SimulationConfig& c) {
        return ValueText{config::FormatEvents(std::invoke(access, c), c.start_stamp, key, codec)};
      },
      "s from the start", std::move(doc));
}

// The placement keys every sensor but the imu has.
Schema<sim::SensorPlacement> PlacementSchema() {
  using P = sim::SensorPlacement;
  Schema<P> s;
  s.Key("extrinsic", &P::T_body_sensor, config::ExtrinsicCodec(), "m, deg",
        "T_body_sensor (p_body = T_body_sensor * p_sensor): {translation_m: [x, y, z], rotation_rpy_deg: "
        "[roll, "
        "pitch, yaw]} with R = Rz(yaw) Ry(pitch) Rx(roll), either part optional, or {matrix: [16 numbers, "
        "row-major 4x4]}");
  s.Key(
      "stamp_delay_s", &P::stamp_delay_s, "s",
      "the sensor stamps its data this late (stamp = true time + delay), within +-10; calibration_true.yaml "
      "states time_offset_s = -delay, calibration.yaml 0");
  s.Key("extrinsic_error.rotation_deg", &P::rotation_error_deg, "deg",
        "error of the extrinsic the user is given, T_given = T_body_sensor * Exp([t; r]): rotation vector, "
        "sensor frame, norm < 180");
  s.Key("extrinsic_error.translation_m", &P::translation_error_m, "m", "... and translation, sensor frame");
  s.Flow("extrinsic_error");
  return s;
}

Schema<sim::GnssNoise> NoiseSchema(const std::string& quality) {
  using N = sim::GnssNoise;
  Schema<N> s;
  s.Key("horizontal_std_m", &N::horizontal_std_m, "m", quality + ": 1 sigma per horizontal axis");
  s.Key("vertical_std_m", &N::vertical_std_m, "m", quality + ": 1 sigma, up");
  s.Key("correlation_time_s", &N::correlation_time_s, "s",
        quality + ": first-order Gauss-Markov correlation time (0: white)");
  return s;
}

// A sensor's keys under `name`: `enabled`, then its model's.
template <typename Sensor, typename Model>
void AddSensor(Schema<SimulationConfig>& s, const std::string& name, Sensor SimulationConfig::*sensor,
               const std::string& enabled_doc, const Schema<Model>& model) {
  Schema<Sensor> keys;
  keys.Key("enabled", &Sensor::enabled, "", enabled_doc);
  keys.Nest("", &Sensor::model, model);
  s.Nest(name, sensor, keys);
}

// The sensor's placement keys under `name` (after its model's event windows).
template <typename Sensor>
void AddPlacement(Schema<SimulationConfig>& s, const std::string& name, Sensor SimulationConfig::*sensor) {
  s.Nest(
      name, [sensor](auto& c) -> auto& { return (c.*sensor).placement; }, PlacementSchema());
}

void AddTopLevel(Schema<SimulationConfig>& s) {
  using C = SimulationConfig;
  s.Key("scene", &C::scene, "", "urban | wild | warehouse | corridor | tunnel");
  s.Key("seed", &C::seed, "", "integer in [0, 2^64); the same seed gives bit-identical data");
  s.Key("duration_s", &C::duration_s, "s",
        "in (0, 3600]; with a trajectory file: at most this much of it (<= 0: all)");
  s.Key("start_time_s", &C::start_stamp,
        Codec<Stamp>{config::ReadSeconds,
                     [](const Stamp& t) { return ValueText{config::FormatExactSeconds(t)}; }},
        "s since the epoch",
        "the sequence start, exact to the ns, >= 0 (a trajectory file's own stamps win); event windows are "
        "relative to it");
  s.ReadFirst("start_time_s");

  using T = sim::TrajectorySource;
  Schema<T> trajectory;
  trajectory.Key("file", &T::file, "", "TUM, KITTI or EuRoC pose file; \"\": the scene's default trajectory");
  trajectory.Key("format", &T::format, "", "auto | tum | kitti | euroc");
  trajectory.Key("kitti_rate_hz", &T::kitti_rate_hz, "Hz",
                 "in (0, 1000]: KITTI poses have no stamps and are this far apart");
  trajectory.Key(
      "knot_spacing_s", &T::knot_spacing_s, "s",
      "in (0.001, 10]: spline fitted to the poses (continuous acceleration); handheld: at most 0.02");
  trajectory.Key(
      "motion", &T::motion,
      config::NamedCodec<sim::Motion>([](const std::string& name) { return sim::ParseMotion(name); },
                                      [](sim::Motion m) { return std::string(sim::MotionName(m)); }),
      "",
      "vehicle | handheld: how the body moves along the scene's default path (no file): driven, or "
      "carried by a person walking 1.3 m/s, bouncing and looking around (peak body rate 95 deg/s); "
      "the command line's --motion handheld also sets body_height_m 1.4");
  s.Nest("trajectory", &C::trajectory, trajectory);
  s.Flow("trajectory");

  s.Key("body_height_m", &C::body_height_m, "m", "in [0, 100]: body (imu) frame above the ground");
  s.Key("ground_truth_rate_hz", &C::ground_truth_rate_hz, "Hz", "in (0, 10000]: rate of groundtruth.tum");
  using G = GeodeticOrigin;
  Schema<G> origin;
  origin.Key("latitude_deg", &G::latitude_deg, "deg", "world origin (WGS84), in [-90, 90], north positive");
  origin.Key("longitude_deg", &G::longitude_deg, "deg", "in [-180, 180], east positive");
  origin.Key("altitude_m", &G::height_m, "m",
             "above the WGS84 ellipsoid (GeodeticOrigin::height_m), in [-12000, 100000]");
  s.Nest("origin", &C::origin, origin);
  s.Flow("origin");
  s.Key("threads", &C::threads, "",
        "ray-casting threads, >= 0; 0: all cores (the output does not depend on it)");
  s.Key("bag", &C::write_bag, "", "also write a ROS1 bag of the sequence");
}

void AddImu(Schema<SimulationConfig>& s) {
  Schema<ImuNoise> noise;
  noise.Key("accel_noise_density", &ImuNoise::accel_noise_density, "m/s^2/sqrt(Hz)",
            ">= 0: white noise, per-sample std = density * sqrt(rate)");
  noise.Key("gyro_noise_density", &ImuNoise::gyro_noise_density, "rad/s/sqrt(Hz)", ">= 0");
  noise.Key("accel_bias_random_walk", &ImuNoise::accel_bias_random_walk, "m/s^3/sqrt(Hz)",
            ">= 0: the bias std grows as density * sqrt(t)");
  noise.Key("gyro_bias_random_walk", &ImuNoise::gyro_bias_random_walk, "rad/s^2/sqrt(Hz)", ">= 0");
  noise.Key("initial_accel_bias", &ImuNoise::initial_accel_bias, "m/s^2", "imu frame, at the first sample");
  noise.Key("initial_gyro_bias", &ImuNoise::initial_gyro_bias, "rad/s", "imu frame, at the first sample");
  noise.Key("accel_saturation", &ImuNoise::accel_saturation, "m/s^2", "per axis, >= 0; 0: no saturation");
  noise.Key("gyro_saturation", &ImuNoise::gyro_saturation, "rad/s", "per axis, >= 0; 0: no saturation");
  using I = sim::SimulatedImuConfig;
  Schema<I> imu;
  imu.Key("enabled", &I::enabled, "", "the imu is the body frame itself: it has no placement keys");
  imu.Key("rate_hz", &I::rate_hz, "Hz", "in (0, 10000]");
  imu.Nest("", &I::noise, noise);
  s.Nest("imu", &SimulationConfig::imu, imu);
}

void AddLidar(Schema<SimulationConfig>& s) {
  using M = sim::LidarConfig;
  Schema<M> model;
  model.Key("model", &M::model, "", "spinning16 | spinning32 | spinning64 | spinning128 | livox_avia");
  model.Key("rate_hz", &M::rate_hz, "Hz", "sweeps (Livox: frames) per second, in [0.5, 100]");
  model.Key("horizontal_resolution_deg", &M::horizontal_resolution_deg, "deg",
            "spinning only: azimuth step between firings, in (0, 10]");
  model.Key("min_range_m", &M::min_range_m, "m", ">= 0: nearer surfaces block the beam and give no point");
  model.Key("max_range_m", &M::max_range_m, "m",
            "in (min_range_m, 10000]: nothing hit within it gives no point");
  model.Key("range_noise_std_m", &M::range_noise_std_m, "m", ">= 0: Gaussian, along the beam");
  model.Key("dropout_probability", &M::dropout_probability, "", "in [0, 1]: each return lost independently");
  AddSensor(s, "lidar", &SimulationConfig::lidar, "simulate the LiDAR", model);
  s.Key(
      "lidar.keyframe_rate_hz", [](auto& c) -> auto& { return c.lidar.keyframe_rate_hz; }, "Hz",
      "scans written per second, in [0, rate_hz]; 0: every sweep. Sweeps keep their 1 / rate_hz duration; "
      "one in rate_hz / keyframe_rate_hz is cast and written (2 at 10 Hz: every 5th)");
  AddPlacement(s, "lidar", &SimulationConfig::lidar);
}

void AddCamera(Schema<SimulationConfig>& s) {
  using M = sim::CameraConfig;
  Schema<M> model;
  Schema<PinholeIntrinsics> pinhole;
  pinhole.Key("width", &PinholeIntrinsics::width, "px", "in [1, 16384]");
  pinhole.Key("height", &PinholeIntrinsics::height, "px", "in [1, 16384]");
  pinhole.Key("fx", &PinholeIntrinsics::fx, "px",
              "focal length, > 0 (pinhole, OpenCV axes: x right, y down, z forward)");
  pinhole.Key("fy", &PinholeIntrinsics::fy, "px", "focal length, > 0");
  pinhole.Key("cx", &PinholeIntrinsics::cx, "px", "principal point, inside the image");
  pinhole.Key("cy", &PinholeIntrinsics::cy, "px", "principal point, inside the image");
  model.Nest("", &M::pinhole, pinhole);
  model.Key("k1", &M::k1, "", "radial-tangential distortion (rendered exactly)");
  model.Key("k2", &M::k2, "", "radial-tangential distortion");
  model.Key("p1", &M::p1, "", "radial-tangential distortion");
  model.Key("p2", &M::p2, "", "radial-tangential distortion");
  model.Key("k3", &M::k3, "", "radial-tangential distortion");
  model.Key("rate_hz", &M::rate_hz, "Hz", "frames per second, in (0, 1000]; global shutter");
  model.Key("noise_std_dn", &M::noise_std_dn, "DN", "Gaussian pixel noise in 8-bit digital numbers, >= 0");
  model.Key("supersampling", &M::supersampling, "", "n x n rays per pixel (anti-aliasing), in [1, 16]");
  model.Key("sun_direction", &M::sun_direction_world, "", "world frame, towards the sun (normalised)");
  model.Key("ambient", &M::ambient, "", "in [0, 1]: colour * (ambient + (1 - ambient) max(0, n.l))");
  model.Key("exposure", &M::exposure, "", "brightness gain on the linear colour, > 0");
  model.Key("textured", &M::textured, "",
            "false: each material's plain base colour (e.g. calibration targets)");
  AddSensor(s, "camera", &SimulationConfig::camera, "simulate the camera", model);
  Windows(
      s, "camera.darkness", [](auto& c) -> auto& { return c.camera.model.darkness; },
      "[[begin_s, end_s], ...]: illumination x 0.1, noise x 3 inside");
  Events(
      s, "camera.exposure_changes", [](auto& c) -> auto& { return c.camera.model.exposure_changes; }, "gain",
      config::PlainCodec<double>(),
      "[{window: [begin_s, end_s], gain: 2.0}, ...]: gain (> 0) x exposure inside");
  Windows(
      s, "camera.occlusions", [](auto& c) -> auto& { return c.camera.model.occlusions; },
      "[[begin_s, end_s], ...]: a dark band sliding across the lens");
  Windows(
      s, "camera.passing_panels", [](auto& c) -> auto& { return c.camera.model.passing_panels; },
      "[[begin_s, end_s], ...]: a textured panel half the image wide passing across the view");
  AddPlacement(s, "camera", &SimulationConfig::camera);
  s.Key(
      "camera.stereo_baseline_m", [](auto& c) -> auto& { return c.camera.stereo_baseline_m; }, "m",
      "in [0, 10]; > 0: a stereo rig, a second camera (cam1) this far to the right of cam0, same model, "
      "synchronous, given with the rig's exact relative extrinsic");
}

void AddWheel(Schema<SimulationConfig>& s) {
  using M = sim::WheelConfig;
  Schema<M> model;
  model.Key("rate_hz", &M::rate_hz, "Hz", "in (0, 10000]; differential drive: forward speed and yaw rate");
  model.Key("wheel_radius_m", &M::wheel_radius_m, "m", "true wheel radius, > 0");
  model.Key("baseline_m", &M::baseline_m, "m", "true distance between the wheels, > 0");
  model.Key("radius_error", &M::radius_error, "",
            "relative, > -1: the odometry uses radius * (1 + radius_error)");
  model.Key("baseline_error", &M::baseline_error, "",
            "relative, > -1: the odometry uses baseline * (1 + baseline_error)");
  model.Key("encoder_resolution_ticks", &M::encoder_resolution_ticks, "ticks",
            "per wheel revolution, >= 0; 0: continuous");
  model.Key("wheel_speed_noise_std", &M::wheel_speed_noise_std, "rad/s", "per wheel and sample, >= 0");
  AddSensor(s, "wheel", &SimulationConfig::wheel, "simulate the wheel odometry", model);
  Events(
      s, "wheel.slips", [](auto& c) -> auto& { return c.wheel.model.slips; }, "ratio",
      config::PlainCodec<double>(),
      "[{window: [begin_s, end_s], ratio: 0.3}, ...]: wheels turn (1 + ratio) times faster than the ground "
      "(ratio >= -1; -1: locked)");
  Windows(
      s, "wheel.floats", [](auto& c) -> auto& { return c.wheel.model.floats; },
      "[[begin_s, end_s], ...]: wheels off the ground, rates frozen");
  AddPlacement(s, "wheel", &SimulationConfig::wheel);
}

void AddGnss(Schema<SimulationConfig>& s) {
  using M = sim::GnssConfig;
  Schema<M> model;
  model.Key("rate_hz", &M::rate_hz, "Hz", "fixes per second, in (0, 1000]");
  model.Key("quality", &M::quality, QualityCodec(), "",
            "single | rtk_float | rtk_fixed, outside the quality_changes");
  AddSensor(s, "gnss", &SimulationConfig::gnss,
            "simulate the GNSS receiver (an antenna: its orientation does not matter)", model);
  Events(
      s, "gnss.quality_changes", [](auto& c) -> auto& { return c.gnss.model.quality_changes; }, "quality",
      QualityCodec(), "[{window: [begin_s, end_s], quality: rtk_fixed}, ...]; the last wins");
  Windows(
      s, "gnss.outages", [](auto& c) -> auto& { return c.gnss.model.outages; },
      "[[begin_s, end_s], ...]: no fixes inside");
  Events(
      s, "gnss.multipath", [](auto& c) -> auto& { return c.gnss.model.multipath; }, "offset_m",
      config::PlainCodec<Eigen::Vector3d>(),
      "[{window: [begin_s, end_s], offset_m: [east, north, up]}, ...]: added to the fixes");
  for (const auto& quality :
       {std::pair{"rtk_fixed", &sim::GnssConfig::rtk_fixed},
        std::pair{"rtk_float", &sim::GnssConfig::rtk_float}, std::pair{"single", &sim::GnssConfig::single}}) {
    const std::string group = std::string("gnss.noise.") + quality.first;
    const auto noise = quality.second;
    s.Nest(
        group, [noise](auto& c) -> auto& { return c.gnss.model.*noise; }, NoiseSchema(quality.first));
    s.Flow(group);
  }
  AddPlacement(s, "gnss", &SimulationConfig::gnss);
}

Schema<SimulationConfig> MakeSimSchema() {
  Schema<SimulationConfig> s("sim");
  AddTopLevel(s);
  AddImu(s);
  AddLidar(s);
  AddCamera(s);
  AddWheel(s);
  AddGnss(s);
  return s;
}

}  // namespace

std::string_view GnssQualityName(sim::GnssQuality quality) {
  switch (quality) {
    case sim::GnssQuality::kRtkFixed:
      return "rtk_fixed";
    case sim::GnssQuality::kRtkFloat:
      return "rtk_float";
    case sim::GnssQuality::kSingle:
      return "single";
  }
  return "single";
}

Expected<sim::GnssQuality> ParseGnssQuality(std::string_view name) {
  for (sim::GnssQuality quality :
       {sim::GnssQuality::kSingle, sim::GnssQuality::kRtkFloat, sim::GnssQuality::kRtkFixed}) {
    if (GnssQualityName(quality) == name) return quality;
  }
  return Status::Error("unknown GNSS quality '" + std::string(name) + "' (single, rtk_float, rtk_fixed)");
}

std::string EmitSimConfig(const SimulationConfig& config) {
  return "# ultrafusion simulation config: `ultrafusion sim --config FILE` reads it back exactly.\n"
         "# Keys are documented in docs/CONFIG.md. Event windows are [begin_s, end_s] in seconds from\n"
         "# start_time_s; extrinsics are T_body_sensor (body = imu frame) as row-major 4x4 matrices.\n" +
         config::EmitSection(config::SimSchema(), config);
}

namespace config {

const Schema<SimulationConfig>& SimSchema() { return BuiltOnce<MakeSimSchema>(); }

}  // namespace config
}  // namespace uf::app
