// EuRoC ASL (MAV) folders: mav0/imuN/data.csv and mav0/camN/data.csv (+ images in camN/data/), each with a
// sensor.yaml, merged by stamp.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>
#include <tuple>

#include "odometry/io/camera_calibration.h"
#include "odometry/io/folders/csv_sources.h"
#include "odometry/io/folders/folder_common.h"
#include "odometry/io/folders/folder_readers.h"

namespace uf {
namespace {

namespace fs = std::filesystem;

// "cam1" -> 1 for the given prefix; nullopt when the name is not prefix + digits.
std::optional<int> SensorIndex(const std::string& name, std::string_view prefix) {
  if (!name.starts_with(prefix) || name.size() == prefix.size() || name.size() > prefix.size() + 3)
    return std::nullopt;
  int index = 0;
  const char* begin = name.data() + prefix.size();
  auto [end, error] = std::from_chars(begin, name.data() + name.size(), index);
  if (error != std::errc() || end != name.data() + name.size()) return std::nullopt;
  return index;
}

// sensor.yaml: T_BS {rows: 4, cols: 4, data: [16 row-major numbers]}, rate_hz and, for cameras, the
// intrinsics (camera_calibration.h); the IMU noise densities are left to the configuration.
Status ReadSensorYaml(const fs::path& path, StreamInfo& stream) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};  // optional
  std::ostringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  if (yaml.starts_with("%YAML:")) yaml.erase(0, yaml.find('\n'));  // OpenCV's directive, not YAML 1.2
  const std::string name = path.string();
  try {
    const YAML::Node root = YAML::Load(yaml);
    if (!root.IsMap()) return Status::Error(name + ": not a YAML mapping");
    if (const YAML::Node T = root["T_BS"]) {
      if (!T.IsMap() || !T["data"] || !T["data"].IsSequence())
        return Status::Error(name + ": T_BS needs rows, cols and a data list");
      if (T["rows"].as<int>() != 4 || T["cols"].as<int>() != 4)
        return Status::Error(name + ": T_BS must be 4x4 (rows: 4, cols: 4)");
      auto transform = TransformFromRowMajor(T["data"].as<std::vector<double>>(), name + ": T_BS");
      if (!transform) return transform.status();
      stream.T_body_sensor = *transform;
    }
    if (stream.kind == SensorKind::kCamera && root["intrinsics"]) {
      auto camera = ParseCameraCalibration(root, name);
      if (!camera) return camera.status();
      stream.camera_model = *camera;
    }
    if (const YAML::Node rate = root["rate_hz"]) {
      stream.nominal_rate_hz = rate.as<double>();
      if (!(stream.nominal_rate_hz > 0 && stream.nominal_rate_hz < 1e6))
        return Status::Error(name + ": rate_hz must be a positive rate, found " + rate.as<std::string>());
    }
  } catch (const YAML::Exception& e) {
    return Status::Error(name + ": " + e.what());
  }
  return {};
}

fs::path MavFolder(const fs::path& path) {
  std::error_code error;
  if (fs::is_directory(path / "mav0", error)) return path / "mav0";
  return path;
}

}  // namespace

Expected<std::unique_ptr<DatasetReader>> OpenEurocFolder(const fs::path& path, const DatasetOptions&) {
  const fs::path mav = MavFolder(path);
  std::error_code error;
  if (!fs::is_directory(mav, error))
    return Status::Error(path.string() + ": not a EuRoC folder: no mav0/ folder");

  // Sensor folders: IMUs first, then cameras, each by index (cam2 before cam10).
  struct Sensor {
    bool is_camera;
    int index;
    fs::path folder;
  };
  std::vector<Sensor> sensors;
  for (const auto& entry : fs::directory_iterator(mav, error)) {
    if (!entry.is_directory()) continue;  // leica0, state_groundtruth_estimate0, ... are skipped below
    const std::string name = entry.path().filename().string();
    if (const std::optional<int> imu = SensorIndex(name, "imu"))
      sensors.push_back({false, *imu, entry.path()});
    if (const std::optional<int> cam = SensorIndex(name, "cam"))
      sensors.push_back({true, *cam, entry.path()});
  }
  if (error) return Status::Error(mav.string() + ": cannot list the folder: " + error.message());
  std::sort(sensors.begin(), sensors.end(), [](const Sensor& a, const Sensor& b) {
    return std::tie(a.is_camera, a.index) < std::tie(b.is_camera, b.index);
  });

  DatasetDescription description;
  description.path = path;
  description.format = DatasetFormat::kEuroc;
  std::vector<std::unique_ptr<StreamSource>> sources;
  for (const Sensor& sensor : sensors) {
    const fs::path csv = sensor.folder / "data.csv";
    if (!fs::is_regular_file(csv, error))
      return Status::Error(csv.string() + ": missing; every EuRoC sensor folder has a data.csv");
    StreamInfo stream;
    stream.name = RelativeName(csv, path);
    stream.kind = sensor.is_camera ? SensorKind::kCamera : SensorKind::kImu;
    stream.message_type = sensor.is_camera ? "euroc camera csv + images" : "euroc imu csv";
    if (sensor.is_camera) stream.camera = sensor.index;
    if (!sensor.is_camera) stream.imu_accel_unit = "m/s^2";
    if (Status s = ReadSensorYaml(sensor.folder / "sensor.yaml", stream); !s.ok()) return s;
    auto source = sensor.is_camera ? OpenCameraCsv(csv, sensor.folder / "data", sensor.index, stream.name)
                                   : OpenImuCsv(csv);
    if (!source) return source.status();
    description.streams.push_back(std::move(stream));
    sources.push_back(std::move(*source));
  }
  if (sources.empty())
    return Status::Error(mav.string() + ": no imuN/ or camN/ sensor folders with a data.csv");

  const fs::path ground_truth = mav / "state_groundtruth_estimate0" / "data.csv";
  if (fs::is_regular_file(ground_truth, error)) description.ground_truth = ground_truth;

  auto reader = MergedStreamsReader::Create(std::move(description), std::move(sources));
  if (!reader) return reader.status();
  return std::unique_ptr<DatasetReader>(std::move(*reader));
}

}  // namespace uf
