// Umeyama's closed-form least-squares similarity between matched point sets (IEEE PAMI 13(4), 1991), as evo's
// geometry.umeyama_alignment computes it: the R, t (and s) minimising sum |target_i - (s R source_i + t)|^2.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf {

// kYaw: a rotation about z and a translation only (4 dof), for an estimate whose world is gravity-aligned (z
// up) like the reference's (LIO, VIO, WIO): a tilt of its world against gravity then counts as error, where
// an SE3 alignment would turn it away.
enum class AlignMode { kNone, kSe3, kSim3, kYaw };

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

// Weighted rigid alignment: the T = (R, t) minimising sum_i w_i |target_i - (R source_i + t)|^2. With the
// weighted centroids m_s, m_t and the cross-covariance H = sum_i w_i (target_i - m_t)(source_i - m_s)^T:
//   3D (weighted Umeyama):  H = U D V^T,  R = U diag(1, 1, sign(det U det V)) V^T
//   yaw only (both frames have z up, e.g. gravity-aligned worlds): the 2D Procrustes angle of the centred
//     points, R = Rz(atan2(sum w (x_s y_t - y_s x_t), sum w (x_s x_t + y_s y_t)))
//   t = m_t - R m_s.
// Weights > 0, sizes equal (asserted); the caller checks that the points spread enough to fix the rotation.
SE3 WeightedRigidAlignment(std::span<const Eigen::Vector3d> source, std::span<const Eigen::Vector3d> target,
                           std::span<const double> weights, bool yaw_only);

}  // namespace uf
