// ROS1 bags (format 2.0; uncompressed, bz2 and lz4 chunks) as a DatasetReader.
//
// Topics are read by message type: sensor_msgs/PointCloud2 and livox_ros_driver(2)/CustomMsg -> lidar,
// sensor_msgs/Imu -> imu, sensor_msgs/Image and CompressedImage -> camera (numbered in order of appearance),
// sensor_msgs/NavSatFix -> gnss, nav_msgs/Odometry and geometry_msgs/TwistStamped -> wheel; other types are
// ignored. options.topics, when given, selects exactly those topics as those kinds.
//
// Messages come out in file (record) order, streamed one chunk at a time, so memory stays bounded whatever
// the size of the bag. Stamps are header stamps (the record time when a header stamp is zero, with a
// warning); they are delivered as recorded, also when they go backwards (MeasurementStream orders them).
// IMU acceleration comes out in m/s^2; with options.imu_accel_unit == kAuto the unit of each IMU topic is
// detected when the bag is opened, from the first second of its samples (a second pass over the start of
// the bag; an IMU that starts later than the first 256 MB has its first second held back in Next() instead).
// Damage to single messages is skipped and counted in warnings(); damage to the file is an error naming the
// file and the offset, at open or from Next().
#pragma once

#include <filesystem>
#include <memory>

#include "odometry/io/dataset_options.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/status.h"

namespace uf {

Expected<std::unique_ptr<DatasetReader>> OpenRosBag(const std::filesystem::path& path,
                                                    const DatasetOptions& options);

}  // namespace uf
