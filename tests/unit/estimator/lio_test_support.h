// LIO on the simulator's sequences, shared by the LIO tests: the window's configuration for them and the
// feeding of a dataset's scans and IMU samples.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"

namespace uf::estimator::testing {

// The simulator's default LiDAR mount (simulation_config.h): the true T_imu_lidar.
inline const SE3 kSimImuFromLidar(SO3(), Eigen::Vector3d(0, 0, 0.25));

// LIO with T_imu_lidar, a 0.5 m input voxel (the simulated scenes are close), and only the iteration budget:
// the results do not depend on the load.
inline LidarOdometryConfig SimulatedLioConfig(const SE3& T_imu_lidar = kSimImuFromLidar) {
  LidarOdometryConfig config;
  config.use_imu = true;
  config.T_body_lidar = T_imu_lidar;
  config.input_voxel_m = 0.5;
  config.max_solver_time_s = 10;
  return config;
}

// Feeds the folder's scans and IMU samples to `lio` in time order (`before_scan` first sees each scan's
// stamp), then Finish.
inline void FeedLio(const std::filesystem::path& folder, LidarOdometry& lio,
                    const std::function<void(LidarOdometry&, Stamp)>& before_scan = {}) {
  auto reader = OpenDataset(folder.string());
  ASSERT_TRUE(reader.ok()) << reader.error();
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data)) {
      if (before_scan) before_scan(lio, scan->stamp);
      return lio.AddScan(*scan);
    }
    if (const auto* sample = std::get_if<ImuSample>(&m.data)) return lio.AddImu(*sample);
    return Status();
  });
  EXPECT_TRUE(read.ok()) << read.message();
  lio.Finish();
}

}  // namespace uf::estimator::testing
