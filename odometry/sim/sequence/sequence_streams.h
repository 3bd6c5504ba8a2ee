// The streams of a simulated sequence and what is said about them: names, kinds, rates, and the true and
// given calibrations. Internal to the sequence generator.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/rosbag/ros_bag_writer.h"
#include "odometry/sim/sequence/simulation_config.h"

namespace uf::sim {

// One enabled sensor: its stream in the dataset and its topic in the bag.
struct SequenceStream {
  SensorKind kind = SensorKind::kImu;
  std::string name;      // "imu", "lidar", "cam0", "wheel", "gnss"
  BagTopic topic;        // "/imu/data", ...
  double rate_hz = 0.0;  // measurements per second: for the LiDAR, its keyframe rate where one is set
  // LiDAR: scans written per second (SimulatedLidarConfig::keyframe_rate_hz); 0: every sweep.
  double keyframe_rate_hz = 0.0;
  std::optional<SensorPlacement> placement;  // none for the imu (it is the body frame)
  Stamp stamp_delay = 0;                     // ns
  int camera = -1;                           // cameras: 0 for cam0, 1 for cam1 (the stereo rig's right)
};

// The enabled sensors in a fixed order: imu, lidar, cam0, cam1 (a stereo rig's right camera), wheel, gnss.
std::vector<SequenceStream> SequenceStreams(const SimulationConfig& config);

// truth: the extrinsics used to simulate and time_offset = -stamp_delay; otherwise what the user is given
// (extrinsics with the injected errors, time offsets 0).
Calibration SequenceCalibration(const SimulationConfig& config, const std::vector<SequenceStream>& streams,
                                bool truth);

// The dataset writer's stream list, carrying the given calibration.
std::vector<StreamInfo> DatasetStreams(const SimulationConfig& config,
                                       const std::vector<SequenceStream>& streams);

}  // namespace uf::sim
