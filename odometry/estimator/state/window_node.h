// A state of a sliding window (the LiDAR and the wheel-inertial windows share it): its stamp and its two
// parameter blocks, and what the windows do with all their nodes at once: save and restore them around a
// solve, and check them for divergence.
//
// Windows keep their nodes in a std::deque and grow and shrink it only at the ends, so the blocks keep
// their addresses, which the factor graph and the marginalization prior hold.
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/state/nav_state.h"

namespace uf::estimator {

using PoseArray = std::array<double, kPoseSize>;
using SpeedBiasArray = std::array<double, kSpeedBiasSize>;

struct WindowNode {
  Stamp stamp = 0;
  PoseArray pose{};             // T_world_body
  SpeedBiasArray speed_bias{};  // [v, b_a, b_g] (nav_state.h); unused without an IMU
};

NavState NodeNavState(const WindowNode& node);

// A node as the providers see it (GNSS, providers/gnss_provider.h): its stamp and its blocks.
struct NodeView {
  Stamp stamp = 0;
  double* pose = nullptr;        // T_world_body, 7 (nav_state.h)
  double* speed_bias = nullptr;  // [v, b_a, b_g], 9
};
std::vector<NodeView> NodeViews(std::deque<WindowNode>& nodes);

// The blocks of every node, to restore after a failed solve.
struct SavedStates {
  std::vector<PoseArray> poses;
  std::vector<SpeedBiasArray> speed_biases;
};
SavedStates Save(const std::deque<WindowNode>& nodes);
void Restore(const SavedStates& saved, std::deque<WindowNode>& nodes);  // the same nodes as saved
bool AllFinite(const std::deque<WindowNode>& nodes);

// Why the states are not to be trusted: a non-finite block, or (check_speed) a speed above max_speed_mps;
// nullopt when they are.
std::optional<std::string> DivergenceReason(const std::deque<WindowNode>& nodes, bool check_speed,
                                            double max_speed_mps);

}  // namespace uf::estimator
