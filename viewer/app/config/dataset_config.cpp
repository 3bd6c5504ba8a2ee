#include "viewer/app/config/dataset_config.h"

#include <yaml-cpp/yaml.h>

#include "viewer/app/config/config_sections.h"

namespace uf::app {
namespace {

// Errors read "FILE: dataset.KEY (line N): what ... 'value'".
class Section {
 public:
  Section(std::string file, std::string path) : file_(std::move(file)), path_(std::move(path)) {}

  Status Error(const YAML::Node& node, const std::string& key, const std::string& what) const {
    std::string where = file_ + ": " + path_ + (key.empty() ? "" : "." + key);
    if (node.IsDefined() && node.Mark().line >= 0)
      where += " (line " + std::to_string(node.Mark().line + 1) + ")";
    return Status::Error(where + ": " + what);
  }
  Section Child(const std::string& key) const { return Section(file_, path_ + "." + key); }

 private:
  std::string file_, path_;
};

std::string Scalar(const YAML::Node& node) {
  return node.IsScalar() ? node.Scalar() : std::string("<not a scalar>");
}

Expected<Stamp> ParseSecondsNode(const Section& section, const YAML::Node& node, const std::string& key) {
  std::optional<Stamp> value = node.IsScalar() ? ParseSeconds(node.Scalar()) : std::nullopt;
  if (!value) return section.Error(node, key, "expected a number of seconds, got '" + Scalar(node) + "'");
  return *value;
}

Status ParseTopics(const Section& section, const YAML::Node& node, DatasetOptions& options) {
  if (!node.IsSequence()) return section.Error(node, "", "expected a list of {topic, kind}");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node entry = node[i];
    const Section at = section.Child(std::to_string(i));
    if (!entry.IsMap()) return at.Error(entry, "", "expected {topic: NAME, kind: KIND}");
    TopicSelection selection;
    for (const auto& kv : entry) {
      const std::string key = kv.first.as<std::string>();
      if (key == "topic") {
        selection.topic = Scalar(kv.second);
      } else if (key == "kind") {
        const std::optional<SensorKind> kind = ParseSensorKind(Scalar(kv.second));
        if (!kind) {
          return at.Error(
              kv.second, key,
              "unknown sensor kind '" + Scalar(kv.second) + "' (imu, lidar, camera, wheel, gnss)");
        }
        selection.kind = *kind;
      } else {
        return at.Error(kv.first, key, "unknown key (expected topic, kind)");
      }
    }
    if (selection.topic.empty()) return at.Error(entry, "topic", "missing");
    if (!entry["kind"]) return at.Error(entry, "kind", "missing");
    options.topics.push_back(selection);
  }
  return {};
}

Status ParseDatasetSection(const Section& section, const YAML::Node& node, DatasetConfig& config) {
  if (!node.IsMap()) return section.Error(node, "", "expected a map of settings");
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node& value = kv.second;
    if (key == "format") {
      Expected<DatasetFormat> format = ParseDatasetFormat(Scalar(value));
      if (!format) return section.Error(value, key, format.error());
      config.reader.format = *format;
    } else if (key == "topics") {
      if (Status s = ParseTopics(section.Child(key), value, config.reader); !s.ok()) return s;
    } else if (key == "imu_accel_unit") {
      const std::string unit = Scalar(value);
      if (unit == "auto")
        config.reader.imu_accel_unit = ImuAccelUnit::kAuto;
      else if (unit == "m/s^2")
        config.reader.imu_accel_unit = ImuAccelUnit::kMetersPerSecond2;
      else if (unit == "g")
        config.reader.imu_accel_unit = ImuAccelUnit::kStandardGravity;
      else
        return section.Error(value, key, "expected auto, m/s^2 or g, got '" + unit + "'");
    } else if (key == "derive_point_times_from_azimuth") {
      const std::string flag = Scalar(value);
      if (flag != "true" && flag != "false")
        return section.Error(value, key, "expected true or false, got '" + flag + "'");
      config.reader.derive_point_times_from_azimuth = flag == "true";
    } else if (key == "lidar_sweep_period_s") {
      Expected<Stamp> period = ParseSecondsNode(section, value, key);
      if (!period) return period.status();
      if (*period <= 0) return section.Error(value, key, "must be positive, got '" + Scalar(value) + "'");
      config.reader.lidar_sweep_period_s = ToSeconds(*period);
    } else if (key == "folder_scan_stamp") {
      const std::string position = Scalar(value);
      if (position == "sweep_middle")
        config.reader.folder_scan_stamp = ScanStampPosition::kSweepMiddle;
      else if (position == "sweep_start")
        config.reader.folder_scan_stamp = ScanStampPosition::kSweepStart;
      else
        return section.Error(value, key, "expected sweep_middle or sweep_start, got '" + position + "'");
    } else if (key == "time_offsets_s") {
      if (!value.IsMap())
        return section.Error(value, key, "expected a map of stream name or kind to seconds");
      for (const auto& offset : value) {
        const std::string name = offset.first.as<std::string>();
        Expected<Stamp> seconds = ParseSecondsNode(section.Child(key), offset.second, name);
        if (!seconds) return seconds.status();
        config.stream.time_offsets[name] = *seconds;
      }
    } else if (key == "reorder_window_s") {
      Expected<Stamp> window = ParseSecondsNode(section, value, key);
      if (!window) return window.status();
      if (*window < 0) return section.Error(value, key, "must not be negative, got '" + Scalar(value) + "'");
      config.stream.reorder_window = *window;
    } else {
      return section.Error(
          kv.first, key,
          "unknown key (expected format, topics, imu_accel_unit, derive_point_times_from_azimuth, "
          "lidar_sweep_period_s, folder_scan_stamp, time_offsets_s, reorder_window_s)");
    }
  }
  return {};
}

}  // namespace

Expected<DatasetFormat> ParseDatasetFormat(const std::string& name) {
  for (DatasetFormat format : {DatasetFormat::kAuto, DatasetFormat::kRosBag, DatasetFormat::kKittiFolder,
                               DatasetFormat::kEuroc, DatasetFormat::kUltrafusion}) {
    if (DatasetFormatName(format) == name) return format;
  }
  return Status::Error("unknown dataset format '" + name + "' (auto, rosbag, kitti, euroc, ultrafusion)");
}

Expected<DatasetConfig> LoadDatasetConfig(const std::filesystem::path& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    return Status::Error(file.string() + ": cannot open the configuration file");
  } catch (const YAML::Exception& e) {
    return Status::Error(file.string() + ": " + e.what());
  }
  DatasetConfig config;
  if (root.IsNull()) return config;
  if (!root.IsMap()) return Status::Error(file.string() + ": expected a map of sections at the top level");
  try {
    for (const auto& kv : root) {
      const std::string key = kv.first.as<std::string>();
      if (key != "dataset") {
        if (IsKnownConfigSection(key)) continue;  // another reader's section
        return Status::Error(file.string() + ": unknown top-level key '" + key + "' (expected " +
                             KnownConfigSectionsList() + ")");
      }
      if (Status s = ParseDatasetSection(Section(file.string(), "dataset"), kv.second, config); !s.ok())
        return s;
    }
  } catch (const YAML::Exception& e) {
    return Status::Error(file.string() + ": " + e.what());
  }
  return config;
}

}  // namespace uf::app
