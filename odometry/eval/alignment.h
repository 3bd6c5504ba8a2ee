// Umeyama's closed-form least-squares similarity between matched point sets (IEEE PAMI 13(4), 1991), as evo's
// geometry.umeyama_alignment computes it: the R, t (and s) minimising sum |target_i - (s R source_i + t)|^2.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf {

enum class AlignMode { kNone, kSe3, kSim3 };

struct Similarity {
  SO3 rotation;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  // Applies to a pose as evo does: scale the position, then left-multiply by [R|t].
  SE3 operator*(const SE3& pose) const {
    return SE3(rotation * pose.so3(), rotation * (scale * pose.translation()) + translation);
  }
};

// Fails for fewer than 3 pairs or when the source points are degenerate (all on one line or one point).
Expected<Similarity> Umeyama(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, bool with_scale);

}  // namespace uf
