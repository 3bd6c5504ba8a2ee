#include "viewer/pipeline/run/run_mode.h"

#include <algorithm>
#include <array>

namespace uf::pipeline {
namespace {

// The modes that run. The GNSS factor (factors/gnss_factor.h) is not in the window yet: the G modes are
// refused by ParseMode, and auto leaves GNSS to the map's georeference after the run.
constexpr std::array kModes = {
    EstimatorMode{OdometryMode::kLo, false},
    EstimatorMode{OdometryMode::kLio, false},
    EstimatorMode{OdometryMode::kLio, true},
    EstimatorMode{OdometryMode::kLo, true},
};
constexpr std::array<std::string_view, 4> kGnssModes = {"lio+g", "lwgio", "lo+g", "lwgo"};

// What the dataset lacks for the mode ("" when it has everything).
std::string MissingFor(const EstimatorMode& mode, const DatasetDescription& description,
                       const DatasetSensors& sensors) {
  std::vector<std::string> missing;
  if (mode.core == OdometryMode::kLio && sensors.imu < 0)
    missing.push_back("no IMU stream");
  else if (mode.core == OdometryMode::kLio && !sensors.T_imu_lidar)
    missing.push_back("no LiDAR-to-IMU transform (T_body_sensor of " +
                      description.streams[sensors.lidar].name + ")");
  if (mode.wheel && sensors.wheel < 0)
    missing.push_back("no wheel odometry stream");
  else if (mode.wheel && !sensors.T_imu_wheel)
    missing.push_back("no wheel-to-IMU transform (T_body_sensor of " +
                      description.streams[sensors.wheel].name + ")");
  else if (mode.wheel && mode.core == OdometryMode::kLo && !sensors.T_imu_lidar)
    missing.push_back("no wheel-to-LiDAR transform (the LiDAR's T_body_sensor)");
  std::string text;
  for (const std::string& why : missing) text += (text.empty() ? "" : ", ") + why;
  return text;
}

}  // namespace

std::string StreamList(const DatasetDescription& description) {
  std::string list;
  for (const StreamInfo& s : description.streams)
    list += (list.empty() ? "" : ", ") + s.name + " (" + std::string(SensorKindName(s.kind)) + ")";
  return list.empty() ? "none" : list;
}

std::string ModeName(const EstimatorMode& mode) {
  return std::string("l") + (mode.wheel ? "w" : "") + (mode.core == OdometryMode::kLio ? "io" : "o");
}

std::vector<std::string> ModeNames() {
  std::vector<std::string> names = {"auto"};
  for (const EstimatorMode& mode : kModes) names.push_back(ModeName(mode));
  return names;
}

Expected<std::optional<EstimatorMode>> ParseMode(std::string_view text) {
  if (text == "auto") return std::optional<EstimatorMode>();
  for (const EstimatorMode& mode : kModes)
    if (ModeName(mode) == text) return std::optional<EstimatorMode>(mode);
  if (std::find(kGnssModes.begin(), kGnssModes.end(), text) != kGnssModes.end())
    return Status::Error(
        "--mode " + std::string(text) +
        ": the GNSS factor is not in the estimator's window yet (GNSS fixes georeference the "
        "map after the run); use the mode without G");
  if (text == "wio" || text == "wgio")
    return Status::Error(
        "--mode " + std::string(text) +
        ": the estimator is driven by LiDAR scans; modes without a LiDAR are not implemented "
        "yet (use lwio with a LiDAR)");
  std::string names;
  for (const std::string& name : ModeNames()) names += (names.empty() ? "" : ", ") + name;
  return Status::Error("--mode " + std::string(text) + ": unknown mode (one of " + names + ")");
}

Expected<EstimatorMode> ChooseMode(const std::optional<EstimatorMode>& asked,
                                   const DatasetDescription& description, const DatasetSensors& sensors,
                                   std::vector<std::string>& notes) {
  if (asked) {
    const std::string missing = MissingFor(*asked, description, sensors);
    if (missing.empty()) return *asked;
    return Status::Error("--mode " + ModeName(*asked) + ": " + description.path.string() + " has " + missing +
                         " (streams: " + StreamList(description) + ")");
  }
  // Auto stays with the paper's modes: the wheel factors on the inertial core only.
  const bool imu = MissingFor({OdometryMode::kLio, false}, description, sensors).empty();
  const std::string why = MissingFor({OdometryMode::kLio, true}, description, sensors);
  const EstimatorMode mode{imu ? OdometryMode::kLio : OdometryMode::kLo, imu && why.empty()};
  if (!why.empty()) notes.push_back("--mode auto: ran " + ModeName(mode) + " (" + why + ")");
  return mode;
}

}  // namespace uf::pipeline
