// The first value of the GNSS alignment block (factors/gnss_factor.h): the yaw and translation that map the
// window's antenna positions onto the fixes, in closed form, once the antenna has moved far enough
// horizontally for the yaw to be seen.
//
// Pairs (a_i = antenna in the world, b_i = fix in ENU, weight w_i > 0), W = sum w_i. The world is
// gravity-aligned, so the rotation is about z only and the horizontal and vertical parts separate (the
// yaw-only case of uf::WeightedRigidAlignment, types/alignment.h, computes it):
//   horizontal (2D weighted Procrustes), on the x-y components:
//     c_a = sum w_i a_i / W,  c_b = sum w_i b_i / W,  A_i = a_i - c_a,  B_i = b_i - c_b
//     yaw = atan2(sum w_i (A_i x B_i), sum w_i (A_i . B_i))      (A x B = A_x B_y - A_y B_x)
//     (t_e, t_n) = c_b - Rz(yaw) c_a
//   this yaw maximises sum w_i B_i . Rz A_i, i.e. minimises sum w_i |Rz A_i - B_i|^2;
//   vertical: t_u = sum w_i (b_i,z - a_i,z) / W.
// The residual RMS is sqrt(mean_i |Rz(yaw) a_i + t - b_i|^2) (unweighted, m). A weight from a fix's
// covariance: HorizontalWeight = 2 / (S_ee + S_nn), the inverse of the mean horizontal variance.
#pragma once

#include <Eigen/Core>
#include <span>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/factors/gnss_factor.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct AlignmentPair {
  Eigen::Vector3d antenna_world;  // a_i: the window's pose at the fix time times the lever arm, m
  Eigen::Vector3d fix_enu;        // b_i: the fix in the GNSS ENU frame, m
  double weight = 1.0;            // w_i > 0
};

struct AlignmentInit {
  EnuAlignment alignment;   // p_enu = Rz(yaw) p_world + t
  double rms_m = 0.0;       // residual RMS of the pairs
  double baseline_m = 0.0;  // HorizontalBaseline of the pairs
  int pairs = 0;
};

// The largest horizontal distance of an antenna position (world) from the first one, m.
double HorizontalBaseline(std::span<const AlignmentPair> pairs);

// 2 / (S_ee + S_nn) of an ENU covariance S.
double HorizontalWeight(const Eigen::Matrix3d& covariance);

// Fails, saying why, with fewer than config.min_alignment_fixes pairs, a non-finite value or a weight that
// is not positive, a baseline under config.min_alignment_baseline_m (the yaw is not observable yet), or a
// residual RMS above config.max_alignment_rms_m.
Expected<AlignmentInit> InitializeAlignment(std::span<const AlignmentPair> pairs,
                                            const GnssFactorConfig& config);

}  // namespace uf::estimator
