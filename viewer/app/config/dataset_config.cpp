// The `dataset:` section: its schema (every key once) and the codecs of its lists, names and seconds.
#include "viewer/app/config/dataset_config.h"

#include "viewer/app/config/section_schemas.h"
#include "viewer/app/config/sim_config_values.h"

namespace uf::app {
namespace {

using config::Codec;
using config::KeyPath;
using config::NamedCodec;
using config::Schema;
using config::ValueText;

Expected<SensorKind> ParseKind(const std::string& name) {
  if (std::optional<SensorKind> kind = ParseSensorKind(name)) return *kind;
  return Status::Error("unknown sensor kind '" + name + "' (imu, lidar, camera, wheel, gnss)");
}

// An extrinsic that may be absent: not written then.
Codec<std::optional<SE3>> OptionalExtrinsicCodec() {
  return {[](const KeyPath& at, const YAML::Node& node, std::optional<SE3>& T) -> Status {
            SE3 read;
            if (Status s = config::ExtrinsicCodec().read(at, node, read); !s.ok()) return s;
            T = read;
            return {};
          },
          [](const std::optional<SE3>& T) {
            if (T) return config::ExtrinsicCodec().write(*T);
            ValueText value{"none"};
            value.omitted = true;
            return value;
          }};
}

const Schema<TopicSelection>& TopicSchema() {
  static const Schema<TopicSelection> schema = [] {
    Schema<TopicSelection> s;
    s.Key("topic", &TopicSelection::topic, "", "the ROS topic");
    s.Key(
        "kind", &TopicSelection::kind,
        NamedCodec<SensorKind>(ParseKind, [](SensorKind kind) { return std::string(SensorKindName(kind)); }),
        "", "the sensor kind it is read as");
    s.Key("T_body_sensor", &TopicSelection::T_body_sensor, OptionalExtrinsicCodec(), "",
          "optional: where the sensor sits on the body ({translation_m, rotation_rpy_deg} or {matrix}); "
          "bags carry no calibration the reader uses");
    return s;
  }();
  return schema;
}

// [{topic: NAME, kind: KIND}, ...], both keys required; written one per line, left out when empty.
Codec<std::vector<TopicSelection>> TopicsCodec() {
  return {[](const KeyPath& at, const YAML::Node& node, std::vector<TopicSelection>& topics) -> Status {
            if (!node.IsSequence())
              return at.Error(node, "expected a list of {topic, kind}, got '" + config::Text(node) + "'");
            std::vector<TopicSelection> read(node.size());
            for (std::size_t i = 0; i < node.size(); ++i) {
              if (!node[i].IsMap() || !node[i]["topic"] || !node[i]["kind"])
                return at[i].Error(node[i],
                                   "expected {topic: NAME, kind: KIND}, got '" + config::Text(node[i]) + "'");
              if (Status s = config::ReadMap(TopicSchema(), at[i], node[i], read[i]); !s.ok()) return s;
              if (read[i].topic.empty()) return (at[i] / "topic").Error(node[i]["topic"], "missing");
            }
            topics = std::move(read);
            return {};
          },
          [](const std::vector<TopicSelection>& topics) {
            ValueText value{"[]"};
            value.omitted = topics.empty();
            for (const TopicSelection& topic : topics)
              value.lines.push_back("- " + config::EmitFlow(TopicSchema(), topic));
            return value;
          }};
}

// {stream name or sensor kind: seconds, ...}; written one per line, left out when empty. A map given
// replaces the base's.
Codec<std::map<std::string, Stamp>> TimeOffsetsCodec() {
  return {[](const KeyPath& at, const YAML::Node& node, std::map<std::string, Stamp>& offsets) -> Status {
            if (!node.IsMap())
              return at.Error(
                  node, "expected a map of stream name or kind to seconds, got '" + config::Text(node) + "'");
            std::map<std::string, Stamp> read;
            for (const auto& kv : node) {
              const std::string name = config::Text(kv.first);
              if (Status s = config::ReadSeconds(at / name, kv.second, read[name]); !s.ok()) return s;
            }
            offsets = std::move(read);
            return {};
          },
          [](const std::map<std::string, Stamp>& offsets) {
            ValueText value{"{}"};
            value.omitted = offsets.empty();
            for (const auto& [name, offset] : offsets)
              value.lines.push_back(config::Format(name) + ": " + FormatSeconds(offset));
            return value;
          }};
}

// Seconds read exactly to the nanosecond; `positive`: > 0, else >= 0.
Status ReadDuration(const KeyPath& at, const YAML::Node& node, bool positive, Stamp& duration) {
  Stamp read = 0;
  if (Status s = config::ReadSeconds(at, node, read); !s.ok()) return s;
  if (positive && read <= 0) return at.Error(node, "must be positive, got '" + config::Text(node) + "'");
  if (read < 0) return at.Error(node, "must not be negative, got '" + config::Text(node) + "'");
  duration = read;
  return {};
}

Codec<double> SweepPeriodCodec() {
  return {[](const KeyPath& at, const YAML::Node& node, double& seconds) -> Status {
            Stamp period = 0;
            if (Status s = ReadDuration(at, node, true, period); !s.ok()) return s;
            seconds = ToSeconds(period);
            return {};
          },
          [](const double& seconds) { return ValueText{config::FormatNumber(seconds)}; }};
}

Codec<Stamp> ReorderWindowCodec() {
  return {[](const KeyPath& at, const YAML::Node& node, Stamp& window) {
            return ReadDuration(at, node, false, window);
          },
          [](const Stamp& window) { return ValueText{FormatSeconds(window)}; }};
}

std::string AccelUnitName(ImuAccelUnit unit) {
  return unit == ImuAccelUnit::kAuto ? "auto" : unit == ImuAccelUnit::kMetersPerSecond2 ? "m/s^2" : "g";
}

Expected<ImuAccelUnit> ParseAccelUnit(const std::string& name) {
  for (ImuAccelUnit unit :
       {ImuAccelUnit::kAuto, ImuAccelUnit::kMetersPerSecond2, ImuAccelUnit::kStandardGravity})
    if (AccelUnitName(unit) == name) return unit;
  return Status::Error("expected auto, m/s^2 or g, got '" + name + "'");
}

std::string StampPositionName(ScanStampPosition position) {
  return position == ScanStampPosition::kSweepMiddle ? "sweep_middle" : "sweep_start";
}

Expected<ScanStampPosition> ParseStampPosition(const std::string& name) {
  for (ScanStampPosition position : {ScanStampPosition::kSweepMiddle, ScanStampPosition::kSweepStart})
    if (StampPositionName(position) == name) return position;
  return Status::Error("expected sweep_middle or sweep_start, got '" + name + "'");
}

// auto (nullopt) or a convention's word (odometry/types/azimuth_convention.h).
Expected<std::optional<AzimuthConvention>> ParsePointTimeConvention(const std::string& name) {
  if (name == "auto") return std::optional<AzimuthConvention>();
  if (std::optional<AzimuthConvention> convention = ParseAzimuthConvention(name)) return convention;
  return Status::Error("expected " + PointTimeConventionWords() + ", got '" + name + "'");
}

std::string AutoOrConventionKey(std::optional<AzimuthConvention> convention) {
  return convention ? AzimuthConventionKey(*convention) : "auto";
}

Schema<DatasetConfig> MakeDatasetSchema() {
  Schema<DatasetOptions> reader;
  reader.Key(
      "format", &DatasetOptions::format,
      NamedCodec<DatasetFormat>(ParseDatasetFormat,
                                [](DatasetFormat format) { return std::string(DatasetFormatName(format)); }),
      "", "auto | rosbag | kitti | euroc | ultrafusion; auto: detected from the path");
  reader.Key("topics", &DatasetOptions::topics, TopicsCodec(), "",
             "ROS bags: read exactly these topics, [{topic: /imu/data, kind: imu}, ...] (kind: imu | lidar | "
             "camera | wheel | gnss); empty: every topic of a known message type");
  reader.Key("imu_accel_unit", &DatasetOptions::imu_accel_unit,
             NamedCodec<ImuAccelUnit>(ParseAccelUnit, AccelUnitName), "",
             "unit of sensor_msgs/Imu linear_acceleration: auto | m/s^2 | g (auto: from the first second's "
             "median norm)");
  reader.Key("derive_point_times_from_azimuth", &DatasetOptions::derive_point_times_from_azimuth, "",
             "spinning LiDARs without per-point times: derive them from the azimuth (false: no point times)");
  reader.Key("point_time_convention", &DatasetOptions::point_time_convention,
             NamedCodec<std::optional<AzimuthConvention>>(ParsePointTimeConvention, AutoOrConventionKey), "",
             "how those times are derived: " + PointTimeConventionWords() +
                 " (spin seen from above, where the sweep starts; none: no deskew); auto: the reader's "
                 "default (KITTI-style folders clockwise_from_behind, bags clockwise_from_first_point, the "
                 "project's format as stored), checked against the first scans by run and info, which take "
                 "the one that fits");
  reader.Key("lidar_sweep_period_s", &DatasetOptions::lidar_sweep_period_s, SweepPeriodCodec(), "s",
             "sweep period of LiDARs whose scans do not say when they end (KITTI-style folders), > 0");
  reader.Key("folder_scan_stamp", &DatasetOptions::folder_scan_stamp,
             NamedCodec<ScanStampPosition>(ParseStampPosition, StampPositionName), "",
             "KITTI-style folders: times.txt stamps the sweep's middle (KITTI) or its start: sweep_middle | "
             "sweep_start");
  reader.Key("calibration_file", &DatasetOptions::calibration_file, "",
             "a calibration file (the format of calibration_estimated.yaml of `calibrate` and of the "
             "simulator's calibration.yaml) whose sensors replace the T_body_sensor and add their "
             "time_offset_s to the streams of the same name (a relative path is relative to the working "
             "directory; run records it absolute in config.yaml); empty: the data's own calibration");
  Schema<MeasurementStreamOptions> stream;
  stream.Key(
      "time_offsets_s", &MeasurementStreamOptions::time_offsets, TimeOffsetsCodec(), "s",
      "added to the stamps, by stream name or sensor kind ({lidar: -0.012, /fix: 0.2}); a stream's name "
      "wins over its kind");
  stream.Key("reorder_window_s", &MeasurementStreamOptions::reorder_window, ReorderWindowCodec(), "s",
             "how far (stamp time) a quiet stream may lag before the others are released without it, >= 0");

  Schema<DatasetConfig> s("dataset");
  s.Nest("", &DatasetConfig::reader, reader);
  s.Nest("", &DatasetConfig::stream, stream);
  return s;
}

}  // namespace

std::string PointTimeConventionWords() {
  std::string words = "auto";
  for (const AzimuthSweep sweep : {AzimuthSweep::kClockwise, AzimuthSweep::kCounterClockwise})
    for (const SweepStart start : {SweepStart::kBehind, SweepStart::kAhead, SweepStart::kFirstPoint})
      words += " | " + AzimuthConventionKey({sweep, start});
  return words + " | " + AzimuthConventionKey(kNoDeskew);
}

Expected<DatasetFormat> ParseDatasetFormat(const std::string& name) {
  for (DatasetFormat format : {DatasetFormat::kAuto, DatasetFormat::kRosBag, DatasetFormat::kKittiFolder,
                               DatasetFormat::kKittiRaw, DatasetFormat::kEuroc, DatasetFormat::kUltrafusion}) {
    if (DatasetFormatName(format) == name) return format;
  }
  return Status::Error("unknown dataset format '" + name + "' (auto, rosbag, kitti, kitti_raw, euroc, ultrafusion)");
}

std::string EmitDatasetConfig(const DatasetConfig& config) {
  return config::EmitSection(config::DatasetSchema(), config);
}

namespace config {

const Schema<DatasetConfig>& DatasetSchema() { return BuiltOnce<MakeDatasetSchema>(); }

}  // namespace config
}  // namespace uf::app
