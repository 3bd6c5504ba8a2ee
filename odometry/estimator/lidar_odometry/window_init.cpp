// The LiDAR window's side of the inertial initialization (init/inertial_initializer.h): what an attempt
// sees of the window, and the record (see odometry_window.h; TryInitializeInertial and
// ApplyInertialAlignment are in window_nodes.cpp).
#include <algorithm>

#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {

// The first initialization counts from the first IMU sample (none trimmed yet: the window is not full before
// its first scans); a re-initialization after a divergence from the new window's first node.
Stamp LidarOdometry::Impl::InitializationStart() const {
  if (initializer.started() || imu.empty()) return nodes.front().stamp;
  return imu.OldestStamp();
}

// Every scan of the window with its middle (stamp and current LO pose) and whether it is registered (a
// rejected scan's poses are only predicted), the window's nodes, and with the stationary branch the wheels'
// rest test.
InitWindow LidarOdometry::Impl::InitializationWindow() const {
  InitWindow out;
  for (const ScanState& scan : window) {
    const Stamp begin = NodeAt(scan.begin_node).stamp, end = NodeAt(scan.end_node).stamp;
    out.scans.push_back({scan.id, begin, begin + (end - begin) / 2,
                         PoseAt(NodePose(scan.begin_node), NodePose(scan.end_node), 0.5), scan.in_map});
  }
  for (const Node& n : nodes) {
    out.node_stamps.push_back(n.stamp);
    out.node_poses.push_back(PoseFromBlock(n.pose.data()));
  }
  if (wheel && config.wheel.stationary_updates)
    out.wheels_at_rest = [this](Stamp from, Stamp to) { return wheel->AtRest(from, to); };
  return out;
}

const InitializationRecord& LidarOdometry::initialization_record() const {
  return impl_->initializer.record();
}

}  // namespace uf::estimator
