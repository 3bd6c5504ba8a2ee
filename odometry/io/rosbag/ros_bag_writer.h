// Writes measurements into a ROS1 bag with standard message types, through librosbag (rosbag::Bag), so
// that any ROS tool and the project's own reader can play it:
//   imu     sensor_msgs/Imu          (orientation_covariance[0] = -1: no orientation)
//   lidar   sensor_msgs/PointCloud2  fields x y z intensity (float32), t (uint32 ns after the header stamp,
//                                    the Ouster convention: exact), ring (uint16); header stamp = scan start
//   camera  sensor_msgs/CompressedImage, format "png" (the frame's PNG/JPEG bytes, or the image encoded)
//   wheel   nav_msgs/Odometry        (twist in the child frame; pose left at identity: not measured)
//   gnss    sensor_msgs/NavSatFix    (status: no_fix -1, fix 0, sbas 1, rtk_float and rtk_fixed 2 = GBAS,
//                                    so RTK fixed reads back as rtk_float; covariance type KNOWN)
// The record time of each message is its header stamp. Write in time order (as a recorder would): readers
// that merge streams expect the bag roughly ordered. The bag is written under a temporary name and renamed
// by Finish(); without Finish() nothing is left behind.
//
// This header is free of ROS types: the implementation is compiled as C++17 (ROS message headers do not
// compile as C++20).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "odometry/io/measurement.h"
#include "odometry/types/status.h"

namespace uf {

struct BagTopic {
  std::string topic;     // "/imu/data"
  std::string frame_id;  // header.frame_id ("imu_link"); wheel: the child frame, "odom" is the parent
  SensorKind kind = SensorKind::kImu;
};

class RosBagWriter {
 public:
  // LZ4-compressed chunks. Fails (naming the path) when the file cannot be created.
  static Expected<RosBagWriter> Create(const std::filesystem::path& path, std::vector<BagTopic> topics);

  RosBagWriter(RosBagWriter&&) noexcept;
  RosBagWriter& operator=(RosBagWriter&&) noexcept;
  ~RosBagWriter();

  // Writes one measurement on topics[topic]; its kind must match the topic's.
  Status Write(int topic, const MeasurementData& data);

  // Closes the bag and renames it into place.
  Status Finish();

 private:
  struct State;
  explicit RosBagWriter(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace uf
