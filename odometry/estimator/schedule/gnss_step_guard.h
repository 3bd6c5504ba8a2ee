// The GNSS's hysteresis in the reliability scheduling (docs/METHOD.md "Factor-wise reliability scheduling",
// GNSS step guard): multipath moves the fixes by a step, from one fix to the next, where the odometry's
// drift moves the innovation only gradually. The innovation test alone (gnss/integrity_check.h) lets a
// lasting offset in once its prediction uncertainty, growing with the distance driven since the last
// accepted fix, covers it (a 5 m multipath after ~15 m); the guard holds such fixes out until the
// innovation comes back.
//
// With e_k the innovation of fix k (fix minus prediction, ENU) and Sigma_k its covariance, consecutive fixes
// (at most max_gap_s apart) step when
//   (e_k - e_k-1)^T (Sigma_k + Sigma_k-1 + (q m)^2 I + s_0^2 I)^-1 (e_k - e_k-1) > gate
// (m: the antenna's predicted motion between them, q the odometry's relative drift per distance, s_0 the
// prediction's jitter from fix to fix), e_k-1 taken under the window's current estimate when the caller can
// give it: an accepted fix after a gap moves the window, and with it every later innovation, by a step that
// is no multipath. A step starts a hold: fix k and the following ones stay out until one
// is back at the level before the step (the same test against e_k-1, m counted from there), or max_hold_s
// have passed (the step was the odometry's, or the fixes' new level is right: the innovation test decides
// again).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "odometry/types/stamp.h"

namespace uf::estimator {

struct GnssStepRule {
  double gate = 16.27;           // chi-square, 3 dof (the innovation test's)
  double drift_fraction = 0.01;  // q, per metre moved (WIO drifts ~0.7 %, LIO less)
  double jitter_m = 0.1;         // s_0
  double max_gap_s = 1.0;        // consecutive fixes further apart are not compared
  double max_hold_s = 30.0;      // a hold ends after this whatever the fixes do; 0: no guard
};

class GnssStepGuard {
 public:
  explicit GnssStepGuard(const GnssStepRule& rule) : rule_(rule) {}

  // One fix, in time order, after the innovation test: whether the guard lets it be used (a fix the guard
  // lets through still needs the innovation test's acceptance). antenna: its predicted position (world);
  // previous_now: the previous fix's innovation under the current estimate, if known.
  bool Admit(Stamp stamp, const Eigen::Vector3d& innovation, const Eigen::Matrix3d& covariance,
             const Eigen::Vector3d& antenna,
             const std::optional<Eigen::Vector3d>& previous_now = std::nullopt);
  bool holding() const { return hold_.has_value(); }
  // Squared Mahalanobis distance of the last fix's innovation from the previous one's (or, holding, from the
  // level before the step): what the guard tested.
  double last_step_d2() const { return last_step_d2_; }
  // Forget the fixes (a restart of the window or of the alignment).
  void Reset();

 private:
  struct Seen {
    Stamp stamp = 0;
    Eigen::Vector3d innovation, antenna;
    Eigen::Matrix3d covariance;
  };
  double StepD2(const Seen& from, const Seen& to) const;

  GnssStepRule rule_;
  std::optional<Seen> previous_;
  std::optional<Seen> hold_;  // the fix before the step, while holding
  Stamp hold_start_ = 0;
  double last_step_d2_ = 0;
};

}  // namespace uf::estimator
