// The window behind InertialOdometry (private to this library): the node grid, the nodes, the IMU and wheel
// streams and the factor graph. The design is described in inertial_odometry.h; the methods live in
// inertial_odometry.cpp (flow), window_init.cpp (initialization, restarts) and window_solve.cpp (nodes,
// solve, marginalization, keyframes).
//
// LinkNode(id) links each new node to the one before it (IMU, wheel) before the solve that follows; the GNSS
// provider (WGIO) links the fixes the nodes cover before each solve (Solve in window_solve.cpp), through
// NodeViews(nodes) (state/window_node.h); the visual provider (VIO, VWIO) observes each node's frame when
// it is pushed, and links its landmarks before each solve.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/inertial_odometry/inertial_odometry.h"
#include "odometry/estimator/init/inertial_alignment.h"
#include "odometry/estimator/preintegration/imu_buffer.h"
#include "odometry/estimator/providers/gnss_provider.h"
#include "odometry/estimator/providers/visual_provider.h"
#include "odometry/estimator/providers/wheel_provider.h"
#include "odometry/estimator/state/window_node.h"
#include "odometry/estimator/window/factor_graph.h"

namespace uf::estimator {

struct InertialOdometry::Impl {
  Impl(const InertialOdometryConfig& c, std::unique_ptr<VisualProvider> camera)
      : config(c), imu(c.imu, c.imu_max_gap_s), wheel(c.wheel, c.T_body_wheel), visual(std::move(camera)) {
    AttachProviders();
    if (config.use_gnss) gnss = std::make_unique<GnssProvider>(config.gnss, config.T_body_gnss.translation());
  }

  InertialOdometryConfig config;
  FactorGraph graph;
  ImuBuffer imu;
  WheelProvider wheel;
  std::unique_ptr<GnssProvider> gnss;      // WGIO
  std::unique_ptr<VisualProvider> visual;  // VIO, VWIO
  std::deque<WindowNode> nodes;        // ids first_node_id ...; the factors ending at node id carry tag id
  long first_node_id = 0;
  // The grid's next node (with the camera: the earliest stamp a frame's node may have), once the streams
  // have begun.
  std::optional<Stamp> next_stamp;
  std::vector<Stamp> init_stamps;      // before initialization: the waiting nodes
  SE3 restart_pose;                    // T_world_imu where the next initialization starts ...
  std::optional<Stamp> restart_stamp;  // ... and when (none at the very start: the first node's)
  bool inertial = false;
  std::string init_summary, last_init_failure;
  std::vector<Keyframe> finished;
  std::map<long, ImuReliability> imu_scores;  // of the IMU factors that left the window, by tag
  std::vector<std::string> warnings;
  std::vector<InertialOdometryStats> processed;
  std::vector<TrackedFrame> tracked_frames;  // the front end's, per frame since the last take

  // Flow (inertial_odometry.cpp).
  void ProcessReady(bool flush);
  std::optional<Stamp> NextNodeStamp() const;
  void AttachProviders();
  void AddNodeAt(Stamp stamp);
  void SolveAndSlide(InertialOdometryStats& stats);
  void TrimStreams();

  // Initialization and restarts (window_init.cpp).
  void TryInitialize();
  Expected<InertialAlignment> Align(std::vector<SE3>& poses);
  Expected<InertialAlignment> VisualInertialAlignment(std::vector<SE3>& poses);
  Expected<std::vector<SE3>> DeadReckon(const std::vector<Stamp>& stamps) const;
  Status Start(const InertialAlignment& alignment, const std::vector<SE3>& poses);
  double GyroBiasPriorSigma(const InertialAlignment& alignment) const;
  void Restart(bool keep_window);

  // Nodes, solve, marginalization (window_solve.cpp).
  WindowNode& NodeAt(long id) { return nodes[static_cast<std::size_t>(id - first_node_id)]; }
  long LastNodeId() const { return first_node_id + static_cast<long>(nodes.size()) - 1; }
  SE3 NodePose(long id) { return PoseFromBlock(NodeAt(id).pose.data()); }
  long PushNode(const WindowNode& node);
  void LinkNode(long id, ImuPreintegration imu_preintegration);
  void AddGaugePrior();
  std::optional<ImuReliability> TakeImuScore(long id);
  bool Solve(int* iterations, int* outliers);
  void MarginalizeOldest(double* ms);
  void ReleaseOldest();
};

}  // namespace uf::estimator
