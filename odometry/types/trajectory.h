// A sequence of poses, with nanosecond stamps when the source has them (a KITTI pose file without a
// times file has none, and is then associated by index).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"

namespace uf {

struct Trajectory {
  std::vector<Stamp> stamps;  // empty, or one per pose, strictly increasing
  std::vector<SE3> poses;     // T_world_frame for each stamp

  std::size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
  bool has_stamps() const { return !stamps.empty(); }

  // The pose at time t: the stored pose at one of the stamps, else interpolated between the bracketing poses
  // t_i < t < t_i+1 (uf::Interpolate: slerp of the rotation, lerp of the translation) at
  // s = (t - t_i) / (t_i+1 - t_i). None outside [first stamp, last stamp] (no extrapolation) or without
  // stamps.
  std::optional<SE3> PoseAt(Stamp t) const;
};

// The translation of each pose.
inline std::vector<Eigen::Vector3d> Positions(const std::vector<SE3>& poses) {
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(poses.size());
  for (const SE3& pose : poses) positions.push_back(pose.translation());
  return positions;
}

}  // namespace uf
