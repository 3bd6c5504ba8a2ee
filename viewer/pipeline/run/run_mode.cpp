#include "viewer/pipeline/run/run_mode.h"

#include <algorithm>
#include <array>

namespace uf::pipeline {
namespace {

// The modes that run.
constexpr std::array kModes = {
    EstimatorMode{OdometryMode::kLo, false, false},
    EstimatorMode{OdometryMode::kLio, false, false},
    EstimatorMode{OdometryMode::kLio, true, false},
    EstimatorMode{OdometryMode::kLo, true, false},
    EstimatorMode{OdometryMode::kLio, false, true},
    EstimatorMode{OdometryMode::kLio, true, true},
    EstimatorMode{OdometryMode::kWio, true, false},
    EstimatorMode{OdometryMode::kWio, true, true},
    EstimatorMode{OdometryMode::kWio, false, false, true},
    EstimatorMode{OdometryMode::kWio, true, false, true},
    EstimatorMode{OdometryMode::kWio, false, true, true},
    EstimatorMode{OdometryMode::kWio, true, true, true},
    EstimatorMode{OdometryMode::kLio, false, false, true},
    EstimatorMode{OdometryMode::kLio, true, false, true},
    EstimatorMode{OdometryMode::kLio, false, true, true},
    EstimatorMode{OdometryMode::kLio, true, true, true},
};

std::string Joined(const std::vector<std::string>& parts) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text;
}

// What the dataset lacks for the mode ("" when it has everything).
std::string MissingFor(const EstimatorMode& mode, const DatasetDescription& description,
                       const DatasetSensors& sensors) {
  std::vector<std::string> missing;
  if (mode.core != OdometryMode::kWio && sensors.lidar < 0)
    missing.push_back("no LiDAR stream");
  else if (mode.core != OdometryMode::kLo && sensors.imu < 0)
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
  if (mode.gnss && sensors.gnss < 0) missing.push_back("no GNSS stream");
  if (mode.camera && sensors.camera < 0)
    missing.push_back("no camera stream with intrinsics");
  else if (mode.camera && !sensors.T_imu_camera)
    missing.push_back("no camera-to-IMU transform (T_body_sensor of " +
                      description.streams[sensors.camera].name + ")");
  return Joined(missing);
}

}  // namespace

std::string StreamList(const DatasetDescription& description) {
  std::string list;
  for (const StreamInfo& s : description.streams)
    list += (list.empty() ? "" : ", ") + s.name + " (" + std::string(SensorKindName(s.kind)) + ")";
  return list.empty() ? "none" : list;
}

std::string ModeName(const EstimatorMode& mode) {
  if (mode.core == OdometryMode::kWio)
    return std::string(mode.camera ? "v" : "") + (mode.wheel ? "w" : "") + (mode.gnss ? "g" : "") + "io";
  const std::string visual = mode.camera ? "v" : "";
  if (mode.gnss && !mode.wheel) return mode.core == OdometryMode::kLio ? "l" + visual + "io+g" : "lo+g";
  return "l" + visual + (mode.wheel ? "w" : "") + (mode.gnss ? "g" : "") +
         (mode.core == OdometryMode::kLio ? "io" : "o");
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
  if (text == "lo+g" || text == "lwgo")
    return Status::Error(
        "--mode " + std::string(text) +
        ": the GNSS factor needs the IMU (its alignment to ENU is a yaw and a translation of a "
        "gravity-aligned world); use lio+g or lwgio, or lo and the map's georeference "
        "after the run");
  std::string names;
  for (const std::string& name : ModeNames()) names += (names.empty() ? "" : ", ") + name;
  return Status::Error("--mode " + std::string(text) + ": unknown mode (one of " + names + ")");
}

namespace {

// Auto on a dataset without a LiDAR: the inertial window with the camera and the wheel when the dataset has
// them (at least one), GNSS factors when there is a GNSS stream; or an error naming what the data lacks.
Expected<EstimatorMode> ChooseWithoutLidar(const DatasetDescription& description,
                                           const DatasetSensors& sensors, std::vector<std::string>& notes) {
  const std::string no_wheel = MissingFor({OdometryMode::kWio, true, false}, description, sensors);
  const std::string no_camera = MissingFor({OdometryMode::kWio, false, false, true}, description, sensors);
  if (!no_wheel.empty() && !no_camera.empty())
    return Status::Error(description.path.string() + ": no LiDAR stream (for lo and lio) and " + no_wheel +
                         " (for wio), " + no_camera + " (for vio) (streams: " + StreamList(description) +
                         ")");
  const EstimatorMode mode{OdometryMode::kWio, no_wheel.empty(), sensors.gnss >= 0, no_camera.empty()};
  std::vector<std::string> left_out = {"no LiDAR stream"};
  for (const std::string* why : {&no_wheel, &no_camera})
    if (!why->empty()) left_out.push_back(*why);
  if (!mode.gnss) left_out.push_back("no GNSS stream");
  notes.push_back("--mode auto: ran " + ModeName(mode) + " (" + Joined(left_out) + ")");
  return mode;
}

}  // namespace

Expected<EstimatorMode> ChooseMode(const std::optional<EstimatorMode>& asked,
                                   const DatasetDescription& description, const DatasetSensors& sensors,
                                   std::vector<std::string>& notes) {
  if (asked) {
    const std::string missing = MissingFor(*asked, description, sensors);
    if (missing.empty()) return *asked;
    return Status::Error("--mode " + ModeName(*asked) + ": " + description.path.string() + " has " + missing +
                         " (streams: " + StreamList(description) + ")");
  }
  if (sensors.lidar < 0) return ChooseWithoutLidar(description, sensors, notes);
  // Auto stays with the paper's modes: the wheel and GNSS factors on the inertial core only.
  const bool imu = MissingFor({OdometryMode::kLio, false, false}, description, sensors).empty();
  EstimatorMode mode{imu ? OdometryMode::kLio : OdometryMode::kLo, false, false};
  std::vector<std::string> left_out;
  if (!imu && sensors.gnss >= 0)
    left_out.push_back("GNSS factors need the IMU: the map is georeferenced after the run");
  if (imu) {
    const std::string no_wheel = MissingFor({OdometryMode::kLio, true, false}, description, sensors);
    const std::string no_gnss = MissingFor({OdometryMode::kLio, false, true}, description, sensors);
    mode.wheel = no_wheel.empty();
    mode.gnss = no_gnss.empty();
    for (const std::string* why : {&no_wheel, &no_gnss})
      if (!why->empty()) left_out.push_back(*why);
  } else {
    left_out.insert(left_out.begin(), MissingFor({OdometryMode::kLio, false, false}, description, sensors));
  }
  if (const std::string why = Joined(left_out); !why.empty())
    notes.push_back("--mode auto: ran " + ModeName(mode) + " (" + why + ")");
  return mode;
}

}  // namespace uf::pipeline
