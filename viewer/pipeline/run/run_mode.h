// The estimator's mode (docs/METHOD.md "Modes"): its core, LiDAR-only (LO), LiDAR-inertial (LIO) or
// inertial without a LiDAR (the WIO window, with the wheel, the camera or both), and the optional factors it
// adds (W: wheel odometry, G: GNSS, V: camera), named as the paper names them: lo, lio, lwio, lio+g, lwgio,
// wio, wgio, vio, vwio, vgio, vwgio, lvio, lvwio, lvio+g, lvwgio (and lwo, wheel factors on LO). `run --mode`
// takes a name or auto, which picks the richest mode the dataset supports and says what it left out and why.
// GNSS needs an inertial core: its alignment to ENU is a yaw and a translation of a gravity-aligned world.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/types/status.h"
#include "viewer/pipeline/run/run_frames.h"

namespace uf::pipeline {

struct EstimatorMode {
  OdometryMode core = OdometryMode::kLo;
  bool wheel = false;   // wheel odometry factors between the nodes (in WIO without the camera always)
  bool gnss = false;    // GNSS position factors (LIO and WIO)
  bool camera = false;  // visual factors (the inertial cores: vio, vwio, vgio, vwgio, lvio, lvwio, ...)

  bool operator==(const EstimatorMode&) const = default;
};

// "lo", "lio", "lwio", "lwo", "lio+g", "lwgio", "wio", "wgio", "vio", "vwio", "vgio", "vwgio", "lvio",
// "lvwio", "lvio+g", "lvwgio".
std::string ModeName(const EstimatorMode& mode);
// "auto" (nullopt) or the name of a mode that runs (ModeName's). "lo+g" and "lwgo" (GNSS without the IMU) are
// errors saying why they do not run; anything else is an error listing the names.
Expected<std::optional<EstimatorMode>> ParseMode(std::string_view text);
// The names --mode accepts, for the command's help and check.
std::vector<std::string> ModeNames();

// "/imu/data (imu), velodyne (lidar)": the streams a dataset has, for messages ("none" without any).
std::string StreamList(const DatasetDescription& description);

// The mode to run: `asked` when the dataset has what it needs (else an error naming the missing stream or
// extrinsic and listing the streams), or with auto the richest one it supports, with a note for each
// factor left out: a LiDAR mode when there is a LiDAR, else the inertial window with the camera (when it
// has intrinsics and an extrinsic), the wheel and GNSS the dataset has (an error when the IMU is missing, or
// both the wheel and the camera).
Expected<EstimatorMode> ChooseMode(const std::optional<EstimatorMode>& asked,
                                   const DatasetDescription& description, const DatasetSensors& sensors,
                                   std::vector<std::string>& notes);

}  // namespace uf::pipeline
