// EmitSimConfig: SimulationConfig -> YAML text that LoadSimConfig reads back to the same struct, bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <numbers>
#include <sstream>
#include <string_view>

#include "odometry/io/folders/ultrafusion_format.h"
#include "viewer/app/config/sim_config.h"

namespace uf::app {
namespace {

using sim::TimeWindow;
using ultrafusion_format::FormatNumber;

// The pieces one after the other (no "literal" + std::string chains: GCC 12 warns falsely on them).
std::string Cat(std::initializer_list<std::string_view> pieces) {
  std::string text;
  for (std::string_view piece : pieces) text += piece;
  return text;
}

// Exact decimal seconds without trailing zeros: 1700000000.5 s, not 1700000000.500000000.
std::string Seconds(Stamp t) {
  std::string text = FormatSeconds(t);
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text;
}

// A YAML double-quoted scalar: any text reads back unchanged.
std::string Quote(const std::string& text) {
  std::string quoted = "\"";
  for (unsigned char c : text) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\x%02x", c);
      quoted += escape;
    } else {
      quoted += static_cast<char>(c);
    }
  }
  return quoted + "\"";
}

std::string Vector(const Eigen::Vector3d& v) {
  return Cat({"[", FormatNumber(v.x()), ", ", FormatNumber(v.y()), ", ", FormatNumber(v.z()), "]"});
}

std::string Bool(bool value) { return value ? "true" : "false"; }

class Writer {
 public:
  explicit Writer(Stamp start) : start_(start) {}

  void Key(int indent, const std::string& key, const std::string& value, const std::string& comment = "") {
    out_ << std::string(2 * indent, ' ') << key << ":" << (value.empty() ? "" : " ") << value
         << (comment.empty() ? "" : "  # ") << comment << "\n";
  }
  void Comment(const std::string& text) { out_ << "# " << text << "\n"; }

  // [begin_s, end_s] relative to the sequence start.
  std::string Window(const TimeWindow& w) const {
    return Cat({"[", Seconds(w.begin - start_), ", ", Seconds(w.end - start_), "]"});
  }
  std::string Windows(const std::vector<TimeWindow>& windows) const {
    std::string list;
    for (const TimeWindow& w : windows) list += (list.empty() ? "" : ", ") + Window(w);
    return "[" + list + "]";
  }
  // [{window: [b, e], KEY: value}, ...] with `format` writing the value.
  template <typename T, typename Format>
  std::string Events(const std::vector<std::pair<TimeWindow, T>>& events, const std::string& key,
                     Format format) const {
    std::string list;
    for (const auto& [window, value] : events)
      list += (list.empty() ? "" : ", ") +
              Cat({"{window: ", Window(window), ", ", key, ": ", format(value), "}"});
    return "[" + list + "]";
  }

  // The placement keys: the extrinsic as an exact 4x4 matrix, its translation and roll-pitch-yaw in a
  // comment.
  void Placement(const sim::SensorPlacement& placement) {
    const Eigen::Matrix4d M = placement.T_body_sensor.matrix();
    std::string matrix;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (r > 0 || c > 0) matrix += c == 0 ? ",  " : ", ";  // two spaces between rows
        matrix += FormatNumber(M(r, c));
      }
    }
    // R = Rz(yaw) Ry(pitch) Rx(roll) has first column (cy cp, sy cp, -sp) and last row (-sp, cp sr, cp cr)
    // (c = cos, s = sin), so roll = atan2(R21, R22), pitch = -asin(R20), yaw = atan2(R10, R00), away from
    // pitch = +-90 deg.
    const Eigen::Matrix3d& R = placement.T_body_sensor.rotation();
    const auto degrees = [](double radians) { return radians * 180.0 / std::numbers::pi + 0.0; };  // no -0
    const Eigen::Vector3d t = placement.T_body_sensor.translation() + Eigen::Vector3d::Zero();
    char comment[200];
    std::snprintf(comment, sizeof(comment),
                  "translation_m [%.6g, %.6g, %.6g], rotation_rpy_deg [%.6g, %.6g, %.6g]", t.x(), t.y(),
                  t.z(), degrees(std::atan2(R(2, 1), R(2, 2))),
                  degrees(-std::asin(std::clamp(R(2, 0), -1.0, 1.0))), degrees(std::atan2(R(1, 0), R(0, 0))));
    Key(2, "extrinsic", "{matrix: [" + matrix + "]}", comment);
    Key(2, "stamp_delay_s", FormatNumber(placement.stamp_delay_s));
    Key(2, "extrinsic_error",
        Cat({"{rotation_deg: ", Vector(placement.rotation_error_deg),
             ", translation_m: ", Vector(placement.translation_error_m), "}"}));
  }

  std::string str() const { return out_.str(); }

 private:
  Stamp start_;
  std::ostringstream out_;
};

std::string Noise(const sim::GnssNoise& noise) {
  return Cat({"{horizontal_std_m: ", FormatNumber(noise.horizontal_std_m),
              ", vertical_std_m: ", FormatNumber(noise.vertical_std_m),
              ", correlation_time_s: ", FormatNumber(noise.correlation_time_s), "}"});
}

}  // namespace

std::string EmitSimConfig(const sim::SimulationConfig& config) {
  const auto N = [](double value) { return FormatNumber(value); };
  Writer w(config.start_stamp);
  w.Comment("ultrafusion simulation config: `ultrafusion sim --config FILE` reads it back exactly.");
  w.Comment("Keys are documented in configs/sim.yaml. Event windows are [begin_s, end_s] in seconds from");
  w.Comment("start_time_s; extrinsics are T_body_sensor (body = imu frame) as row-major 4x4 matrices.");
  w.Key(0, "sim", "");
  w.Key(1, "scene", Quote(config.scene));
  w.Key(1, "seed", std::to_string(config.seed));
  w.Key(1, "duration_s", N(config.duration_s));
  w.Key(1, "start_time_s", Seconds(config.start_stamp));
  const sim::TrajectorySource& trajectory = config.trajectory;
  w.Key(1, "trajectory",
        Cat({"{file: ", Quote(trajectory.file), ", format: ", Quote(trajectory.format), ", kitti_rate_hz: ",
             N(trajectory.kitti_rate_hz), ", knot_spacing_s: ", N(trajectory.knot_spacing_s), "}"}));
  w.Key(1, "body_height_m", N(config.body_height_m));
  w.Key(1, "ground_truth_rate_hz", N(config.ground_truth_rate_hz));
  w.Key(1, "origin",
        Cat({"{latitude_deg: ", N(config.origin.latitude_deg), ", longitude_deg: ",
             N(config.origin.longitude_deg), ", altitude_m: ", N(config.origin.altitude_m), "}"}));
  w.Key(1, "threads", std::to_string(config.threads));
  w.Key(1, "bag", Bool(config.write_bag));

  const ImuNoise& imu = config.imu.noise;
  w.Key(1, "imu", "");
  w.Key(2, "enabled", Bool(config.imu.enabled));
  w.Key(2, "rate_hz", N(config.imu.rate_hz));
  w.Key(2, "accel_noise_density", N(imu.accel_noise_density));
  w.Key(2, "gyro_noise_density", N(imu.gyro_noise_density));
  w.Key(2, "accel_bias_random_walk", N(imu.accel_bias_random_walk));
  w.Key(2, "gyro_bias_random_walk", N(imu.gyro_bias_random_walk));
  w.Key(2, "initial_accel_bias", Vector(imu.initial_accel_bias));
  w.Key(2, "initial_gyro_bias", Vector(imu.initial_gyro_bias));
  w.Key(2, "accel_saturation", N(imu.accel_saturation));
  w.Key(2, "gyro_saturation", N(imu.gyro_saturation));

  const sim::LidarConfig& lidar = config.lidar.model;
  w.Key(1, "lidar", "");
  w.Key(2, "enabled", Bool(config.lidar.enabled));
  w.Key(2, "model", Quote(lidar.model));
  w.Key(2, "rate_hz", N(lidar.rate_hz));
  w.Key(2, "horizontal_resolution_deg", N(lidar.horizontal_resolution_deg));
  w.Key(2, "min_range_m", N(lidar.min_range_m));
  w.Key(2, "max_range_m", N(lidar.max_range_m));
  w.Key(2, "range_noise_std_m", N(lidar.range_noise_std_m));
  w.Key(2, "dropout_probability", N(lidar.dropout_probability));
  w.Placement(config.lidar.placement);

  const sim::CameraConfig& camera = config.camera.model;
  w.Key(1, "camera", "");
  w.Key(2, "enabled", Bool(config.camera.enabled));
  w.Key(2, "width", std::to_string(camera.width));
  w.Key(2, "height", std::to_string(camera.height));
  for (const auto& [key, value] : {std::pair{"fx", camera.fx},
                                   {"fy", camera.fy},
                                   {"cx", camera.cx},
                                   {"cy", camera.cy},
                                   {"k1", camera.k1},
                                   {"k2", camera.k2},
                                   {"p1", camera.p1},
                                   {"p2", camera.p2},
                                   {"k3", camera.k3},
                                   {"rate_hz", camera.rate_hz},
                                   {"noise_std_dn", camera.noise_std_dn}})
    w.Key(2, key, N(value));
  w.Key(2, "supersampling", std::to_string(camera.supersampling));
  w.Key(2, "sun_direction", Vector(camera.sun_direction_world));
  w.Key(2, "ambient", N(camera.ambient));
  w.Key(2, "exposure", N(camera.exposure));
  w.Key(2, "textured", Bool(camera.textured));
  w.Key(2, "darkness", w.Windows(camera.darkness));
  w.Key(2, "exposure_changes", w.Events(camera.exposure_changes, "gain", N));
  w.Key(2, "occlusions", w.Windows(camera.occlusions));
  w.Placement(config.camera.placement);

  const sim::WheelConfig& wheel = config.wheel.model;
  w.Key(1, "wheel", "");
  w.Key(2, "enabled", Bool(config.wheel.enabled));
  w.Key(2, "rate_hz", N(wheel.rate_hz));
  w.Key(2, "wheel_radius_m", N(wheel.wheel_radius_m));
  w.Key(2, "baseline_m", N(wheel.baseline_m));
  w.Key(2, "radius_error", N(wheel.radius_error));
  w.Key(2, "baseline_error", N(wheel.baseline_error));
  w.Key(2, "encoder_resolution_ticks", N(wheel.encoder_resolution_ticks));
  w.Key(2, "wheel_speed_noise_std", N(wheel.wheel_speed_noise_std));
  w.Key(2, "slips", w.Events(wheel.slips, "ratio", N));
  w.Key(2, "floats", w.Windows(wheel.floats));
  w.Placement(config.wheel.placement);

  const sim::GnssConfig& gnss = config.gnss.model;
  const auto quality = [](sim::GnssQuality q) { return std::string(GnssQualityName(q)); };
  w.Key(1, "gnss", "");
  w.Key(2, "enabled", Bool(config.gnss.enabled));
  w.Key(2, "rate_hz", N(gnss.rate_hz));
  w.Key(2, "quality", quality(gnss.quality));
  w.Key(2, "quality_changes", w.Events(gnss.quality_changes, "quality", quality));
  w.Key(2, "outages", w.Windows(gnss.outages));
  w.Key(2, "multipath", w.Events(gnss.multipath, "offset_m", Vector));
  w.Key(2, "noise", "");
  w.Key(3, "rtk_fixed", Noise(gnss.rtk_fixed));
  w.Key(3, "rtk_float", Noise(gnss.rtk_float));
  w.Key(3, "single", Noise(gnss.single));
  w.Placement(config.gnss.placement);
  return w.str();
}

}  // namespace uf::app
