#include "viewer/app/config/config_file.h"

#include <array>
#include <string_view>

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

constexpr std::array<std::string_view, 7> kSections = {"dataset", "sim", "calibration", "lo",
                                                       "lio",     "wio", "splat"};

std::string SectionList() {
  std::string list;
  for (std::string_view section : kSections) list += (list.empty() ? "" : ", ") + std::string(section);
  return list;
}

Status ReadSections(const std::string& name, const YAML::Node& root, ConfigFile& config) {
  for (const auto& kv : root) {
    const std::string key = config::Text(kv.first);
    Status status;
    if (key == "dataset") {
      status = config::ReadSection(config::DatasetSchema(), name, kv.second, config.dataset);
    } else if (key == "lo") {
      status = config::ReadSection(config::LoSchema(), name, kv.second, config.odometry);
    } else if (key == "lio") {
      status = config::ReadSection(config::LioSchema(), name, kv.second, config.odometry);
    } else if (key == "wio") {
      status = config::ReadSection(config::WioSchema(), name, kv.second, config.wio);
    } else if (key == "splat") {
      status = config::ReadSection(config::SplatSchema(), name, kv.second, config.splat);
    } else if (key == "sim") {
      status = config::ReadSection(config::SimSchema(), name, kv.second, config.sim);
    } else if (key != "calibration") {
      return Status::Error(name + " (line " + std::to_string(kv.first.Mark().line + 1) +
                           "): unknown top-level key '" + key + "' (expected " + SectionList() + ")");
    }
    if (!status.ok()) return status;
  }
  return {};
}

}  // namespace

Expected<ConfigFile> LoadConfigFile(const std::filesystem::path& file, ConfigFile base) {
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
    if (Status s = ReadSections(name, root, base); !s.ok()) return s;
  } catch (const YAML::Exception& e) {  // not expected: the readers check types before converting
    return Status::Error(name + ": " + e.what());
  }
  estimator::LidarOdometryConfig odometry = base.odometry;
  odometry.use_imu = false;  // the lio: keys are checked when the mode is known (LidarOdometry::Create)
  if (Status s = odometry.Validate(); !s.ok()) return Status::Error(name + ": " + s.message());
  estimator::InertialOdometryConfig wio = base.wio;
  wio.use_gnss = true;  // its gnss keys are checked whether or not the mode uses them
  if (Status s = wio.Validate(); !s.ok()) return Status::Error(name + ": " + s.message());
  if (Status s = base.splat.Validate(); !s.ok()) return Status::Error(name + ": splat." + s.message());
  return base;
}

}  // namespace uf::app
