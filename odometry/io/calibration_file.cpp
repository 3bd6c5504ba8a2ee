#include "odometry/io/calibration_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <iterator>
#include <set>
#include <sstream>

#include "odometry/io/atomic_file.h"
#include "odometry/io/camera_calibration.h"
#include "odometry/io/folders/folder_common.h"
#include "odometry/io/folders/ultrafusion_format.h"
#include "odometry/io/folders/yaml_keys.h"

namespace uf {
namespace {

using ultrafusion_format::FormatNumber;

void EmitSensor(YAML::Emitter& yaml, const SensorCalibration& sensor) {
  yaml << YAML::BeginMap;
  yaml << YAML::Key << "name" << YAML::Value << sensor.name;
  yaml << YAML::Key << "kind" << YAML::Value << std::string(SensorKindName(sensor.kind));
  yaml << YAML::Key << "T_body_sensor" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double value : RowMajor(sensor.T_body_sensor)) yaml << FormatNumber(value);
  yaml << YAML::EndSeq;
  yaml << YAML::Key << "time_offset_s" << YAML::Value << FormatSeconds(sensor.time_offset);
  if (sensor.camera_model) {
    yaml << YAML::Key << "intrinsics" << YAML::Value << YAML::BeginMap;
    EmitCameraCalibration(yaml, *sensor.camera_model);
    yaml << YAML::EndMap;
  }
  yaml << YAML::EndMap;
}

Expected<SensorCalibration> ParseSensor(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) return Status::Error(where + ": expected a map of sensor settings");
  if (Status s = CheckKeys(node, {"name", "kind", "T_body_sensor", "time_offset_s", "intrinsics"}, where);
      !s.ok())
    return s;
  for (const char* key : {"name", "kind", "T_body_sensor"})
    if (!node[key]) return Status::Error(where + ": missing key '" + key + "'");
  SensorCalibration sensor;
  sensor.name = node["name"].as<std::string>();
  const std::string kind = node["kind"].as<std::string>();
  const std::optional<SensorKind> parsed = ParseSensorKind(kind);
  if (!parsed) return Status::Error(where + ".kind: '" + kind + "' is not imu, lidar, camera, wheel or gnss");
  sensor.kind = *parsed;
  auto transform =
      TransformFromRowMajor(node["T_body_sensor"].as<std::vector<double>>(), where + ".T_body_sensor");
  if (!transform) return transform.status();
  sensor.T_body_sensor = *transform;
  if (const YAML::Node offset = node["time_offset_s"]) {
    const std::optional<Stamp> seconds = offset.IsScalar() ? ParseSeconds(offset.Scalar()) : std::nullopt;
    if (!seconds) return Status::Error(where + ".time_offset_s: not a number of seconds");
    sensor.time_offset = *seconds;
  }
  if (const YAML::Node intrinsics = node["intrinsics"]) {
    if (sensor.kind != SensorKind::kCamera)
      return Status::Error(where + ".intrinsics: given for a " + kind + " sensor");
    auto model = ParseCameraCalibration(intrinsics, where + ".intrinsics");
    if (!model) return model.status();
    sensor.camera_model = *model;
  }
  return sensor;
}

Expected<Calibration> ParseCalibration(const YAML::Node& root, const std::string& file) {
  const std::string where = file + ": calibration";
  const YAML::Node section = root.IsMap() ? root["calibration"] : YAML::Node();
  if (!section) return Status::Error(file + ": no 'calibration:' section");
  if (!section.IsMap()) return Status::Error(where + ": expected a map");
  if (Status s = CheckKeys(section, {"body_frame", "sensors"}, where); !s.ok()) return s;
  Calibration calibration;
  if (section["body_frame"]) calibration.body_frame = section["body_frame"].as<std::string>();
  const YAML::Node sensors = section["sensors"];
  if (!sensors || !sensors.IsSequence()) return Status::Error(where + ".sensors: expected a list of sensors");
  std::set<std::string> names;
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    auto sensor = ParseSensor(sensors[i], where + ".sensors." + std::to_string(i));
    if (!sensor) return sensor.status();
    if (!names.insert(sensor->name).second)
      return Status::Error(where + ".sensors." + std::to_string(i) + ".name: '" + sensor->name +
                           "' appears twice");
    calibration.sensors.push_back(std::move(*sensor));
  }
  return calibration;
}

// Writes `yaml` after `header` as '#' comment lines, atomically.
Status WriteYaml(const std::filesystem::path& path, const YAML::Emitter& yaml, const std::string& header) {
  AtomicFileWriter file(path.string());
  if (Status s = file.status(); !s.ok()) return s;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) file.stream() << "# " << line << '\n';
  file.stream() << yaml.c_str() << '\n';
  return file.Commit();
}

// A camera intrinsics file: the keys of camera_calibration.h at the top level, and no others.
Expected<std::shared_ptr<const CameraModel>> ParseCameraIntrinsics(const YAML::Node& root,
                                                                   const std::string& file) {
  if (!root.IsMap()) return Status::Error(file + ": expected a map of camera intrinsics");
  for (const auto& kv : root) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<not a scalar>");
    if (std::find_if(std::begin(kCameraCalibrationKeys), std::end(kCameraCalibrationKeys),
                     [&key](const char* known) { return key == known; }) == std::end(kCameraCalibrationKeys))
      return Status::Error(file + ": " + key + " (line " + std::to_string(kv.first.Mark().line + 1) +
                           "): unknown key (expected camera_model, distortion_model, intrinsics, "
                           "distortion_coefficients, resolution)");
  }
  return ParseCameraCalibration(root, file);
}

// `parse` (root node, file name) on the YAML file at `path`; errors name the file (and a syntax error's
// line).
template <typename Parse>
auto ParseYamlFile(const std::filesystem::path& path, const char* cannot_open, Parse parse)
    -> decltype(parse(YAML::Node(), std::string())) {
  const std::string file = path.string();
  try {
    return parse(YAML::LoadFile(file), file);
  } catch (const YAML::BadFile&) {
    return Status::Error(file + ": " + cannot_open);
  } catch (const YAML::Exception& e) {
    return Status::Error(file + " (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
}

}  // namespace

const SensorCalibration* Calibration::Find(const std::string& name) const {
  for (const SensorCalibration& sensor : sensors)
    if (sensor.name == name) return &sensor;
  return nullptr;
}

Status WriteCalibrationFile(const std::filesystem::path& path, const Calibration& calibration,
                            const std::string& header) {
  YAML::Emitter yaml;
  yaml << YAML::BeginMap << YAML::Key << "calibration" << YAML::Value << YAML::BeginMap;
  yaml << YAML::Key << "body_frame" << YAML::Value << calibration.body_frame;
  yaml << YAML::Key << "sensors" << YAML::Value << YAML::BeginSeq;
  for (const SensorCalibration& sensor : calibration.sensors) EmitSensor(yaml, sensor);
  yaml << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
  return WriteYaml(path, yaml, header);
}

Expected<Calibration> ReadCalibrationFile(const std::filesystem::path& path) {
  return ParseYamlFile(path, "cannot open", ParseCalibration);
}

Expected<std::shared_ptr<const CameraModel>> ReadCameraIntrinsicsFile(const std::filesystem::path& path) {
  return ParseYamlFile(path, "cannot open the camera file", ParseCameraIntrinsics);
}

Status WriteCameraIntrinsicsFile(const std::filesystem::path& path, const CameraModel& model,
                                 const std::string& header) {
  YAML::Emitter yaml;
  yaml << YAML::BeginMap;
  EmitCameraCalibration(yaml, model);
  yaml << YAML::EndMap;
  return WriteYaml(path, yaml, header);
}

}  // namespace uf
