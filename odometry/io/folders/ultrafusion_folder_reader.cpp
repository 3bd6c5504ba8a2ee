// The project's own dataset format (described in ultrafusion_dataset_writer.h): dataset.yaml names the
// streams; the per-stream files are merged by stamp.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "odometry/io/camera_calibration.h"
#include "odometry/io/folders/csv_sources.h"
#include "odometry/io/folders/folder_common.h"
#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/folders/lidar_record_file.h"
#include "odometry/io/folders/ultrafusion_format.h"
#include "odometry/io/folders/yaml_keys.h"

namespace uf {
namespace {

namespace fs = std::filesystem;

// lidar.bin, one record per Advance().
class LidarRecordSource : public StreamSource {
 public:
  LidarRecordSource(LidarRecordReader reader, std::string stream,
                    std::optional<AzimuthConvention> point_time_convention)
      : reader_(std::move(reader)),
        stream_(std::move(stream)),
        point_time_convention_(point_time_convention) {}

  Expected<bool> Advance() override {
    const std::uint64_t offset = reader_.offset();
    auto scan = reader_.Next();
    if (!scan) return scan.status();
    if (!*scan) return false;
    if (std::string order = order_.Check((*scan)->stamp); !order.empty())
      return Status::Error(stream_ + ": byte offset " + std::to_string(offset) + ": " + order);
    scan_ = std::move(**scan);
    return true;
  }
  Stamp stamp() const override { return scan_.stamp; }

  Expected<std::optional<MeasurementData>> Load(StreamInfo& info, WarningLog& warnings) override {
    const std::size_t before = scan_.points.size();
    std::erase_if(scan_.points, [](const LidarPoint& p) {
      return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.intensity);
    });
    if (scan_.points.size() != before)
      warnings.Add(info.name, "points with NaN/Inf values dropped",
                   static_cast<std::int64_t>(before - scan_.points.size()));
    // Times derived from azimuth when the dataset was written: derived again when a convention is given.
    if (scan_.point_times_from_azimuth && point_time_convention_ && scan_.end > scan_.stamp)
      DeriveAzimuthPointTimes(scan_, scan_.end - scan_.stamp, *point_time_convention_);
    if (first_) {
      if (scan_.point_times_from_azimuth) info.azimuth_convention = point_time_convention_;
      info.point_time = scan_.point_times_from_azimuth ? PointTimeConvention::kAzimuth
                        : scan_.has_point_times        ? PointTimeConvention::kRelativeNanoseconds
                                                       : PointTimeConvention::kNone;
      info.point_time_field = scan_.has_point_times ? "offset_ns" : "";
      first_ = false;
    }
    return std::optional<MeasurementData>(std::move(scan_));
  }

 private:
  LidarRecordReader reader_;
  std::string stream_;  // the file, for errors
  std::optional<AzimuthConvention> point_time_convention_;
  IncreasingStamps order_;
  LidarScan scan_;
  bool first_ = true;
};

Expected<std::unique_ptr<StreamSource>> OpenSource(const fs::path& folder, const StreamInfo& info,
                                                   const fs::path& file, const DatasetOptions& options) {
  const fs::path path = folder / file;
  switch (info.kind) {
    case SensorKind::kImu:
      return OpenImuCsv(path);
    case SensorKind::kWheel:
      return OpenWheelCsv(path);
    case SensorKind::kGnss:
      return OpenGnssCsv(path);
    case SensorKind::kCamera:
      return OpenCameraCsv(path, path.parent_path(), info.camera, info.name);
    case SensorKind::kLidar: {
      auto reader = LidarRecordReader::Open(path);
      if (!reader) return reader.status();
      return std::unique_ptr<StreamSource>(std::make_unique<LidarRecordSource>(
          std::move(*reader), path.string(), options.point_time_convention));
    }
  }
  return Status::Error(path.string() + ": unknown stream kind");
}

// One entry of `streams:`.
Expected<StreamInfo> ParseStream(const YAML::Node& node, const std::string& where, fs::path& file) {
  if (!node.IsMap()) return Status::Error(where + ": not a mapping");
  if (Status s = CheckKeys(
          node, {"name", "kind", "file", "camera", "rate_hz", "T_body_sensor", "calibration"}, where);
      !s.ok())
    return s;
  for (const char* key : {"name", "kind", "file"})
    if (!node[key]) return Status::Error(where + ": missing key '" + key + "'");
  StreamInfo info;
  info.name = node["name"].as<std::string>();
  const std::string kind = node["kind"].as<std::string>();
  const std::optional<SensorKind> parsed = ParseSensorKind(kind);
  if (!parsed) return Status::Error(where + ": kind '" + kind + "' is not imu, lidar, camera, wheel or gnss");
  info.kind = *parsed;
  info.message_type = "ultrafusion " + kind;
  file = fs::path(node["file"].as<std::string>());
  if (!IsInsideFolder(file))
    return Status::Error(where + ": file '" + file.string() + "' is not inside the folder");
  if (info.kind == SensorKind::kCamera) {
    if (!node["camera"]) return Status::Error(where + ": camera stream without 'camera' index");
    info.camera = node["camera"].as<int>();
    if (info.camera < 0)
      return Status::Error(where + ": camera index " + std::to_string(info.camera) + " < 0");
  } else if (node["camera"]) {
    return Status::Error(where + ": 'camera' given for a " + kind + " stream");
  }
  if (const YAML::Node calibration = node["calibration"]) {
    if (info.kind != SensorKind::kCamera)
      return Status::Error(where + ": 'calibration' given for a " + kind + " stream");
    if (!calibration.IsMap()) return Status::Error(where + ": calibration: not a mapping");
    if (Status s = CheckKeys(calibration,
                             {"distortion_model", "intrinsics", "distortion_coefficients", "resolution"},
                             where + ": calibration");
        !s.ok())
      return s;
    auto camera = ParseCameraCalibration(calibration, where + ": calibration");
    if (!camera) return camera.status();
    info.camera_model = *camera;
  }
  if (info.kind == SensorKind::kImu) info.imu_accel_unit = "m/s^2";
  if (node["rate_hz"]) {
    info.nominal_rate_hz = node["rate_hz"].as<double>();
    if (!(info.nominal_rate_hz > 0 && std::isfinite(info.nominal_rate_hz)))
      return Status::Error(where + ": rate_hz must be positive");
  }
  if (node["T_body_sensor"]) {
    auto transform =
        TransformFromRowMajor(node["T_body_sensor"].as<std::vector<double>>(), where + ": T_body_sensor");
    if (!transform) return transform.status();
    info.T_body_sensor = *transform;
  }
  return info;
}

// {latitude_deg, longitude_deg, height_m}, all three, finite and in range (ValidateGeodeticOrigin).
Expected<GeodeticOrigin> ParseEnuOrigin(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) return Status::Error(where + ": expected {latitude_deg, longitude_deg, height_m}");
  if (Status s = CheckKeys(node, {"latitude_deg", "longitude_deg", "height_m"}, where); !s.ok()) return s;
  GeodeticOrigin origin;
  for (auto [key, value] :
       {std::pair{"latitude_deg", &origin.latitude_deg}, std::pair{"longitude_deg", &origin.longitude_deg},
        std::pair{"height_m", &origin.height_m}}) {
    if (!node[key]) return Status::Error(where + ": " + key + " missing");
    *value = node[key].as<double>();
  }
  if (Status s = ValidateGeodeticOrigin(origin); !s.ok()) return Status::Error(where + ": " + s.message());
  return origin;
}

}  // namespace

Expected<std::unique_ptr<DatasetReader>> OpenUltrafusionFolder(const fs::path& path,
                                                               const DatasetOptions& options) {
  const fs::path yaml_path = path / ultrafusion_format::kDescriptionFile;
  const std::string where = yaml_path.string();
  std::error_code error;
  if (!fs::is_regular_file(yaml_path, error))
    return Status::Error(where + ": missing; not an ultrafusion dataset folder");
  DatasetDescription description;
  description.path = path;
  description.format = DatasetFormat::kUltrafusion;
  std::vector<std::unique_ptr<StreamSource>> sources;
  try {
    const YAML::Node root = YAML::LoadFile(yaml_path.string());
    if (!root.IsMap()) return Status::Error(where + ": not a YAML mapping");
    if (Status s = CheckKeys(
            root, {"format", "version", "streams", "ground_truth", "ground_truth_enu_origin"}, where);
        !s.ok())
      return s;
    if (!root["format"] || root["format"].as<std::string>() != ultrafusion_format::kFormat)
      return Status::Error(where + ": format must be '" + std::string(ultrafusion_format::kFormat) + "'");
    if (!root["version"] || root["version"].as<int>() != ultrafusion_format::kVersion)
      return Status::Error(where + ": version must be " + std::to_string(ultrafusion_format::kVersion) +
                           " (this reader knows no other)");
    const YAML::Node streams = root["streams"];
    if (!streams || !streams.IsSequence() || streams.size() == 0)
      return Status::Error(where + ": streams must be a non-empty list");
    std::set<std::string> names;
    for (std::size_t i = 0; i < streams.size(); ++i) {
      const std::string stream_where = where + ": streams[" + std::to_string(i) + "]";
      fs::path file;
      auto info = ParseStream(streams[i], stream_where, file);
      if (!info) return info.status();
      if (!names.insert(info->name).second)
        return Status::Error(stream_where + ": stream name '" + info->name + "' used twice");
      if (!fs::is_regular_file(path / file, error))
        return Status::Error((path / file).string() + ": missing (named by " + stream_where + ")");
      auto source = OpenSource(path, *info, file, options);
      if (!source) return source.status();
      description.streams.push_back(std::move(*info));
      sources.push_back(std::move(*source));
    }
    if (const YAML::Node ground_truth = root["ground_truth"]) {
      const fs::path file(ground_truth.as<std::string>());
      if (!IsInsideFolder(file) || !fs::is_regular_file(path / file, error))
        return Status::Error(where + ": ground_truth '" + file.string() + "' is not a file in the folder");
      description.ground_truth = path / file;
    }
    if (const YAML::Node origin = root["ground_truth_enu_origin"]) {
      Expected<GeodeticOrigin> parsed = ParseEnuOrigin(origin, where + ": ground_truth_enu_origin");
      if (!parsed) return parsed.status();
      description.ground_truth_enu_origin = *parsed;
    }
  } catch (const YAML::Exception& e) {
    return Status::Error(where + ": " + e.what());
  }
  auto reader = MergedStreamsReader::Create(std::move(description), std::move(sources));
  if (!reader) return reader.status();
  return std::unique_ptr<DatasetReader>(std::move(*reader));
}

}  // namespace uf
