#include "viewer/pipeline/run/run_mode.h"

#include <algorithm>
#include <array>

namespace uf::pipeline {
namespace {

// "/imu/data (imu), velodyne (lidar)": the streams a dataset has, for messages.
std::string StreamList(const DatasetDescription& description) {
  std::string list;
  for (const StreamInfo& s : description.streams)
    list += (list.empty() ? "" : ", ") + s.name + " (" + std::string(SensorKindName(s.kind)) + ")";
  return list.empty() ? "none" : list;
}

// The modes that run. The GNSS factor (factors/gnss_factor.h) is not in the window yet: the G modes are
// named (ModeName) but refused by ParseMode, and auto leaves GNSS to the map's georeference after the run.
constexpr std::array kModes = {
    EstimatorMode{OdometryMode::kLo, false, false},
    EstimatorMode{OdometryMode::kLio, false, false},
    EstimatorMode{OdometryMode::kLio, true, false},
    EstimatorMode{OdometryMode::kLo, true, false},
};
constexpr std::array<std::string_view, 4> kGnssModes = {"lio+g", "lwgio", "lo+g", "lwgo"};

// Why the dataset cannot give a mode its parts ("" when it can).
std::string MissingFor(const EstimatorMode& mode, const DatasetDescription& description,
                       const DatasetSensors& sensors, bool* imu, bool* wheel, bool* gnss) {
  const std::string& lidar = description.streams[sensors.lidar].name;
  std::string core, w, g;
  if (sensors.imu < 0)
    core = "no IMU stream";
  else if (!sensors.T_imu_lidar)
    core = "no LiDAR-to-IMU transform (T_body_sensor of " + lidar + ")";
  if (sensors.wheel < 0)
    w = "no wheel odometry stream";
  else if (!sensors.T_imu_wheel)
    w = "no wheel-to-IMU transform (T_body_sensor of " + description.streams[sensors.wheel].name + ")";
  else if (mode.core == OdometryMode::kLo && !sensors.T_imu_lidar)
    w = "no wheel-to-LiDAR transform (the LiDAR's T_body_sensor)";
  if (sensors.gnss < 0) g = "no GNSS stream";
  *imu = core.empty(), *wheel = w.empty(), *gnss = g.empty();
  std::string missing;
  for (const auto& [needed, why] :
       {std::pair{mode.core == OdometryMode::kLio, core}, std::pair{mode.wheel, w}, std::pair{mode.gnss, g}})
    if (needed && !why.empty()) missing += (missing.empty() ? "" : ", ") + why;
  return missing;
}

}  // namespace

std::string ModeName(const EstimatorMode& mode) {
  const bool lio = mode.core == OdometryMode::kLio;
  if (mode.gnss && !mode.wheel) return lio ? "lio+g" : "lo+g";
  return std::string("l") + (mode.wheel ? "w" : "") + (mode.wheel && mode.gnss ? "g" : "") +
         (lio ? "io" : "o");
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
        "yet (use lwio or lwgio with a LiDAR)");
  std::string names;
  for (const std::string& name : ModeNames()) names += (names.empty() ? "" : ", ") + name;
  return Status::Error("--mode " + std::string(text) + ": unknown mode (one of " + names + ")");
}

Expected<EstimatorMode> ChooseMode(const std::optional<EstimatorMode>& asked,
                                   const DatasetDescription& description, const DatasetSensors& sensors,
                                   std::vector<std::string>& notes) {
  bool imu = false, wheel = false, gnss = false;
  if (asked) {
    const std::string missing = MissingFor(*asked, description, sensors, &imu, &wheel, &gnss);
    if (missing.empty()) return *asked;
    return Status::Error("--mode " + ModeName(*asked) + ": " + description.path.string() + " has " + missing +
                         " (streams: " + StreamList(description) + ")");
  }
  // Auto stays with the paper's modes: the optional factors on the inertial core only.
  const std::string why =
      MissingFor({OdometryMode::kLio, true, false}, description, sensors, &imu, &wheel, &gnss);
  const EstimatorMode mode{imu ? OdometryMode::kLio : OdometryMode::kLo, imu && wheel, false};
  if (!why.empty()) notes.push_back("--mode auto: ran " + ModeName(mode) + " (" + why + ")");
  return mode;
}

}  // namespace uf::pipeline
