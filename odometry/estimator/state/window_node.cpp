#include "odometry/estimator/state/window_node.h"

#include <Eigen/Core>

namespace uf::estimator {
namespace {

bool Finite(const WindowNode& node) {
  return Eigen::Map<const Eigen::Matrix<double, kPoseSize, 1>>(node.pose.data()).allFinite() &&
         Eigen::Map<const Eigen::Matrix<double, kSpeedBiasSize, 1>>(node.speed_bias.data()).allFinite();
}

}  // namespace

NavState NodeNavState(const WindowNode& node) {
  NavState state;
  state.stamp = node.stamp;
  state.T_world_imu = PoseFromBlock(node.pose.data());
  SetSpeedBias(node.speed_bias.data(), state);
  return state;
}

std::vector<NodeView> NodeViews(std::deque<WindowNode>& nodes) {
  std::vector<NodeView> views;
  views.reserve(nodes.size());
  for (WindowNode& node : nodes) views.push_back({node.stamp, node.pose.data(), node.speed_bias.data()});
  return views;
}

SavedStates Save(const std::deque<WindowNode>& nodes) {
  SavedStates saved;
  for (const WindowNode& node : nodes) {
    saved.poses.push_back(node.pose);
    saved.speed_biases.push_back(node.speed_bias);
  }
  return saved;
}

void Restore(const SavedStates& saved, std::deque<WindowNode>& nodes) {
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    nodes[i].pose = saved.poses[i];
    nodes[i].speed_bias = saved.speed_biases[i];
  }
}

bool AllFinite(const std::deque<WindowNode>& nodes) {
  for (const WindowNode& node : nodes)
    if (!Finite(node)) return false;
  return true;
}

std::optional<std::string> DivergenceReason(const std::deque<WindowNode>& nodes, bool check_speed,
                                            double max_speed_mps) {
  for (const WindowNode& node : nodes) {
    if (!Finite(node)) return "non-finite state at " + StampText(node.stamp);
    const double speed = Eigen::Vector3d(node.speed_bias[0], node.speed_bias[1], node.speed_bias[2]).norm();
    if (check_speed && speed > max_speed_mps)
      return "speed " + std::to_string(speed) + " m/s at " + StampText(node.stamp);
  }
  return std::nullopt;
}

}  // namespace uf::estimator
