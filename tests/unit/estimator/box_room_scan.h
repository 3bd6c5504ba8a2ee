// Synthetic LiDAR scans of a box room for the LiDAR odometry tests, with exact geometry.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "odometry/types/measurements.h"

namespace uf::estimator {

// A box room 20 x 12 x 4 m (with a pillar block so that no direction is degenerate; `other_room`: a room
// 14 x 7 x 3 m with the same pillar, another place that no turn of the first room fits) scanned by a lidar
// turned by `yaw` (rad, about z) whose origin moves as origin + velocity * (t - stamp) during the 0.1 s
// sweep: each azimuth column is cast from the origin at its own time; points are in the lidar frame at that
// time.
inline LidarScan BoxRoomScan(Stamp stamp, const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero(), double yaw = 0,
                             bool other_room = false) {
  LidarScan scan;
  scan.stamp = stamp;
  scan.end = stamp + 100'000'000;
  const Eigen::Vector3d lo = other_room ? Eigen::Vector3d(-5, -3.5, -1.2) : Eigen::Vector3d(-10, -6, -1.5);
  const Eigen::Vector3d hi = other_room ? Eigen::Vector3d(9, 3.5, 1.8) : Eigen::Vector3d(10, 6, 2.5);
  for (int i = 0; i < 360; ++i) {
    for (int k = -8; k <= 8; ++k) {
      const double az = i * M_PI / 180, el = k * 0.08;
      const double t_point = 0.1 * i / 360.0;
      const Eigen::Vector3d from = origin + velocity * t_point;
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      double t = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (d[a] > 1e-9) t = std::min(t, (hi[a] - from[a]) / d[a]);
        if (d[a] < -1e-9) t = std::min(t, (lo[a] - from[a]) / d[a]);
      }
      // Pillar: the slab 3 < x < 4 for y > 2 (its faces x = 3 and y = 2 seen from the room).
      if (d.x() > 1e-9 && from.x() < 3) {
        const double tp = (3 - from.x()) / d.x();
        if (tp < t && from.y() + tp * d.y() > 2) t = tp;
      }
      if (d.y() > 1e-9 && from.y() < 2) {
        const double tp = (2 - from.y()) / d.y();
        const double x = from.x() + tp * d.x();
        if (tp < t && x > 3 && x < 4) t = tp;
      }
      const Eigen::Vector3d p = Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()) * (t * d);
      LidarPoint point;
      point.x = static_cast<float>(p.x());
      point.y = static_cast<float>(p.y());
      point.z = static_cast<float>(p.z());
      point.offset_ns = static_cast<std::int32_t>(i * 100'000'000LL / 360);
      scan.points.push_back(point);
    }
  }
  scan.has_point_times = true;
  return scan;
}

}  // namespace uf::estimator
