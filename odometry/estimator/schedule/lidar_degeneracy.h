// The LiDAR's degeneracy score of the reliability scheduling (docs/METHOD.md "Factor-wise reliability
// scheduling"; paper Sec. III-D): how evenly a scan's point-to-plane factors pin the six directions of its
// pose.
//
// From the information H = sum rho' J^T J of the scan's factors for a rigid move of the scan (tangent
// [dt; dtheta]), each 3x3 block (translation H_tt, rotation H_rr) is scored by its isotropy
//   iso = lambda_min / (trace / 3)   in [0, 1]
// (1: every direction as pinned as the mean one; 0: one direction free, as along a corridor's axis). The
// blocks are taken apart because their units differ (m vs rad: H_rr grows with the range of the points).
// The score is the worse block's, mapped so that a direction with at least kHealthyIsotropy of the mean
// information (its standard deviation within sqrt(1 / 0.1) ~ 3x the mean direction's) counts as pinned:
//   D = 1 - min(1, min(iso_t, iso_r) / kHealthyIsotropy).
// Fewer than 6 matches, or no information, is degenerate (D = 1).
#pragma once

#include "odometry/types/keyframe.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

constexpr double kHealthyIsotropy = 0.1;

LidarDegeneracy AnalyzeLidarInformation(const Matrix6d& information, int matches);

// The LiDAR's scheduling along its weak directions (docs/METHOD.md "Factor-wise reliability scheduling"):
// P = blockdiag(I - sum u u^T, I - sum w w^T) over the eigenvectors u of H_tt and w of H_rr whose eigenvalue
// is below kHealthyIsotropy of their block's mean. A factor's tangent Jacobian times P has no say along them
// (the other sensors carry those directions); P = I when the scan pins every direction or has no
// information.
Matrix6d WeakDirectionProjector(const Matrix6d& information);

// The same beside another sensor that holds the translation with information W (1/m^2, world, over the
// scan's interval): P = blockdiag(I - sum u u^T, I) over the eigenvectors u of H_tt below kHealthyIsotropy
// of their block's mean whose eigenvalue is also below u^T W u, where the other sensor pins the position
// better than the scan does. Rotations stay. (The wheel in the LIO window: docs/METHOD.md "Factor-wise
// reliability scheduling".)
Matrix6d LooseTranslationProjector(const Matrix6d& information, const Eigen::Matrix3d& other_information);

}  // namespace uf::estimator
