// LoadSimConfig: the `sim:` section's keys mapped onto SimulationConfig (the schema is configs/sim.yaml).
#include "viewer/app/config/sim_config.h"

#include "viewer/app/config/config_sections.h"
#include "viewer/app/config/sim_config_yaml.h"

namespace uf::app {

// A GNSS quality by name, for yaml::Value (declared before its use in the templates below).
namespace yaml {
Status Read(const KeyPath& at, const YAML::Node& node, sim::GnssQuality& value) {
  Expected<sim::GnssQuality> quality = ParseGnssQuality(Text(node));
  if (!quality) return at.Error(node, quality.error());
  value = *quality;
  return {};
}
}  // namespace yaml

namespace {

using sim::TimeWindow;
using yaml::Field;
using yaml::KeyPath;
using yaml::List;
using yaml::Value;

// A field holding a map of settings.
Field Section(std::string key, std::vector<Field> fields) {
  return {std::move(key), [fields = std::move(fields)](const KeyPath& at, const YAML::Node& node) {
            return yaml::ReadMap(at, node, fields);
          }};
}

// `windows: [[b, e], ...]`, relative to *start (read when the field is, after start_time_s).
Field Windows(std::string key, std::vector<TimeWindow>& target, const Stamp& start) {
  return List<TimeWindow>(std::move(key), target,
                          [&start](const KeyPath& at, const YAML::Node& node, TimeWindow& window) {
                            return yaml::ReadWindow(at, node, start, window);
                          });
}

// `events: [{window: [b, e], VALUE_KEY: value}, ...]`: both keys required.
template <typename T>
Field Events(std::string key, std::vector<std::pair<TimeWindow, T>>& target, const Stamp& start,
             std::string value_key) {
  using Event = std::pair<TimeWindow, T>;
  return List<Event>(
      std::move(key), target, [&start, value_key](const KeyPath& at, const YAML::Node& node, Event& event) {
        if (!node.IsMap() || !node["window"] || !node[value_key]) {
          return at.Error(node, "expected {window: [begin_s, end_s], " + value_key + ": ...}, got '" +
                                    yaml::Text(node) + "'");
        }
        return yaml::ReadMap(
            at, node,
            {{"window", [&](const KeyPath& w,
                            const YAML::Node& n) { return yaml::ReadWindow(w, n, start, event.first); }},
             Value(value_key, event.second)});
      });
}

// The placement keys every sensor but the imu has.
std::vector<Field> WithPlacement(std::vector<Field> fields, sim::SensorPlacement& placement) {
  fields.push_back({"extrinsic", [&placement](const KeyPath& at, const YAML::Node& node) {
                      return yaml::ReadExtrinsic(at, node, placement.T_body_sensor);
                    }});
  fields.push_back(Value("stamp_delay_s", placement.stamp_delay_s));
  fields.push_back(Section("extrinsic_error", {Value("rotation_deg", placement.rotation_error_deg),
                                               Value("translation_m", placement.translation_error_m)}));
  return fields;
}

Field Imu(sim::SimulatedImuConfig& imu) {
  ImuNoise& noise = imu.noise;
  return Section("imu", {Value("enabled", imu.enabled), Value("rate_hz", imu.rate_hz),
                         Value("accel_noise_density", noise.accel_noise_density),
                         Value("gyro_noise_density", noise.gyro_noise_density),
                         Value("accel_bias_random_walk", noise.accel_bias_random_walk),
                         Value("gyro_bias_random_walk", noise.gyro_bias_random_walk),
                         Value("initial_accel_bias", noise.initial_accel_bias),
                         Value("initial_gyro_bias", noise.initial_gyro_bias),
                         Value("accel_saturation", noise.accel_saturation),
                         Value("gyro_saturation", noise.gyro_saturation)});
}

Field Lidar(sim::SimulatedLidarConfig& lidar) {
  sim::LidarConfig& model = lidar.model;
  return Section("lidar", WithPlacement({Value("enabled", lidar.enabled), Value("model", model.model),
                                         Value("rate_hz", model.rate_hz),
                                         Value("horizontal_resolution_deg", model.horizontal_resolution_deg),
                                         Value("min_range_m", model.min_range_m),
                                         Value("max_range_m", model.max_range_m),
                                         Value("range_noise_std_m", model.range_noise_std_m),
                                         Value("dropout_probability", model.dropout_probability)},
                                        lidar.placement));
}

Field Camera(sim::SimulatedCameraConfig& camera, const Stamp& start) {
  sim::CameraConfig& m = camera.model;
  return Section("camera", WithPlacement({Value("enabled", camera.enabled),
                                          Value("width", m.width),
                                          Value("height", m.height),
                                          Value("fx", m.fx),
                                          Value("fy", m.fy),
                                          Value("cx", m.cx),
                                          Value("cy", m.cy),
                                          Value("k1", m.k1),
                                          Value("k2", m.k2),
                                          Value("p1", m.p1),
                                          Value("p2", m.p2),
                                          Value("k3", m.k3),
                                          Value("rate_hz", m.rate_hz),
                                          Value("noise_std_dn", m.noise_std_dn),
                                          Value("supersampling", m.supersampling),
                                          Value("sun_direction", m.sun_direction_world),
                                          Value("ambient", m.ambient),
                                          Value("exposure", m.exposure),
                                          Value("textured", m.textured),
                                          Windows("darkness", m.darkness, start),
                                          Events("exposure_changes", m.exposure_changes, start, "gain"),
                                          Windows("occlusions", m.occlusions, start)},
                                         camera.placement));
}

Field Wheel(sim::SimulatedWheelConfig& wheel, const Stamp& start) {
  sim::WheelConfig& m = wheel.model;
  return Section(
      "wheel",
      WithPlacement({Value("enabled", wheel.enabled), Value("rate_hz", m.rate_hz),
                     Value("wheel_radius_m", m.wheel_radius_m), Value("baseline_m", m.baseline_m),
                     Value("radius_error", m.radius_error), Value("baseline_error", m.baseline_error),
                     Value("encoder_resolution_ticks", m.encoder_resolution_ticks),
                     Value("wheel_speed_noise_std", m.wheel_speed_noise_std),
                     Events("slips", m.slips, start, "ratio"), Windows("floats", m.floats, start)},
                    wheel.placement));
}

Field Noise(std::string key, sim::GnssNoise& noise) {
  return Section(std::move(key), {Value("horizontal_std_m", noise.horizontal_std_m),
                                  Value("vertical_std_m", noise.vertical_std_m),
                                  Value("correlation_time_s", noise.correlation_time_s)});
}

Field Gnss(sim::SimulatedGnssConfig& gnss, const Stamp& start) {
  sim::GnssConfig& m = gnss.model;
  return Section(
      "gnss", WithPlacement(
                  {Value("enabled", gnss.enabled), Value("rate_hz", m.rate_hz), Value("quality", m.quality),
                   Events("quality_changes", m.quality_changes, start, "quality"),
                   Windows("outages", m.outages, start), Events("multipath", m.multipath, start, "offset_m"),
                   Section("noise", {Noise("rtk_fixed", m.rtk_fixed), Noise("rtk_float", m.rtk_float),
                                     Noise("single", m.single)})},
                  gnss.placement));
}

Status ReadSimSection(const KeyPath& at, const YAML::Node& node, sim::SimulationConfig& config) {
  Field start_time = {"start_time_s", [&config](const KeyPath& key, const YAML::Node& value) {
                        return yaml::ReadSeconds(key, value, config.start_stamp);
                      }};
  // Windows are relative to the start: read start_time_s first, wherever it stands in the section.
  if (node.IsMap() && node["start_time_s"]) {
    if (Status s = start_time.read(at / "start_time_s", node["start_time_s"]); !s.ok()) return s;
  }
  sim::TrajectorySource& trajectory = config.trajectory;
  sim::GeodeticOrigin& origin = config.origin;
  const Stamp& start = config.start_stamp;
  return yaml::ReadMap(
      at, node,
      {Value("scene", config.scene), Value("seed", config.seed), Value("duration_s", config.duration_s),
       start_time,
       Section("trajectory", {Value("file", trajectory.file), Value("format", trajectory.format),
                              Value("kitti_rate_hz", trajectory.kitti_rate_hz),
                              Value("knot_spacing_s", trajectory.knot_spacing_s)}),
       Value("body_height_m", config.body_height_m),
       Value("ground_truth_rate_hz", config.ground_truth_rate_hz),
       Section("origin",
               {Value("latitude_deg", origin.latitude_deg), Value("longitude_deg", origin.longitude_deg),
                Value("altitude_m", origin.altitude_m)}),
       Value("threads", config.threads), Value("bag", config.write_bag), Imu(config.imu), Lidar(config.lidar),
       Camera(config.camera, start), Wheel(config.wheel, start), Gnss(config.gnss, start)});
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

Expected<sim::SimulationConfig> LoadSimConfig(const std::filesystem::path& file, sim::SimulationConfig base) {
  const std::string name = file.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(name);
  } catch (const YAML::BadFile&) {
    return Status::Error(name + ": cannot open the configuration file");
  } catch (const YAML::Exception& e) {
    return Status::Error(name + " (line " + std::to_string(e.mark.line + 1) +
                         "): YAML syntax error: " + e.msg);
  }
  if (root.IsNull()) return base;
  if (!root.IsMap()) return Status::Error(name + ": expected a map of sections at the top level");
  try {
    for (const auto& kv : root) {
      const std::string key = yaml::Text(kv.first);
      if (key == "sim") {
        if (Status s = ReadSimSection(KeyPath(name, "sim"), kv.second, base); !s.ok()) return s;
      } else if (!IsKnownConfigSection(key)) {
        return Status::Error(name + " (line " + std::to_string(kv.first.Mark().line + 1) +
                             "): unknown top-level key '" + key + "' (expected " + KnownConfigSectionsList() +
                             ")");
      }
    }
  } catch (const YAML::Exception& e) {  // not expected: the readers check types before converting
    return Status::Error(name + ": " + e.what());
  }
  return base;
}

}  // namespace uf::app
