// Configuration of the GNSS position factor (factors/gnss_factor.h) and of its gatekeepers in
// odometry/estimator/gnss/: which fixes are used, the covariance each one gets, the 4-dof alignment's start
// and the innovation (integrity) test. The antenna lever arm is not here: it is the GNSS stream's
// T_body_sensor from the dataset's calibration.
#pragma once

#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf::estimator {

// How the covariance a receiver reports for one fix status is turned into the factor's:
//   Sigma = k^2 Sigma_reported, then every eigenvalue raised to at least min_sigma_m^2,
// with k = sigma_scale. A fix with an all-zero covariance (ROS' COVARIANCE_TYPE_UNKNOWN) is rejected, unless
// use_nominal_for_unknown is set: it then gets diag(h^2, h^2, v^2) from the nominal sigmas below (before k
// and the floor). A share `offset_share` of Sigma is a slowly varying offset rather than white noise
// (factors/gnss_offset_factor.h): the fix's factor whitens with (1 - share) Sigma and the offset state
// carries the rest; 0 treats every fix as independent.
struct GnssStatusNoise {
  double min_sigma_m = 0.0;                 // floor of the sigma along every axis, m (> 0)
  double sigma_scale = 1.0;                 // k >= 1: receivers tend to be optimistic
  double nominal_horizontal_sigma_m = 0.0;  // per horizontal axis, m (> 0), for an unknown covariance
  double nominal_vertical_sigma_m = 0.0;    // up, m (> 0), for an unknown covariance
  double offset_share = 0.0;                // in [0, 1)
};

struct GnssFactorConfig {
  // Fixes with a lower status (in GnssFixStatus' order: kNoFix < kFix < kSbas < kRtkFloat < kRtkFixed) are
  // not used. Must not be kNoFix.
  GnssFixStatus min_status = GnssFixStatus::kFix;

  // Per status, {min_sigma_m, sigma_scale, nominal_horizontal_sigma_m, nominal_vertical_sigma_m,
  // offset_share}. Floors a little under the receivers' best case; nominal sigmas of a typical receiver in
  // that mode. A single-point or SBAS fix's error is mostly atmospheric and orbital, the same for tens of
  // seconds, with a receiver noise of decimetres, so about 0.9 of its variance is an offset; that model is
  // opt-in (offset_share 0: white), because on the simulator's single fixes it gains nothing on average
  // (docs/METHOD.md "GNSS factor").
  GnssStatusNoise fix{0.5, 1.0, 2.5, 5.0, 0.0};
  GnssStatusNoise sbas{0.3, 1.0, 1.0, 2.0, 0.0};
  GnssStatusNoise rtk_float{0.05, 1.0, 0.3, 0.5, 0.0};
  GnssStatusNoise rtk_fixed{0.01, 1.0, 0.03, 0.05, 0.0};
  // The offset's correlation time tau, s (> 0), for the statuses whose offset_share is above 0: the
  // atmospheric and orbital errors change over minutes, multipath over tens of seconds.
  double offset_correlation_time_s = 60.0;
  // Use the nominal sigmas for a fix whose covariance is all zero, instead of rejecting it.
  bool use_nominal_for_unknown = false;

  // Innovation test of a fix against the window's prediction: accepted iff d^2 <= integrity_gate, with
  // d^2 = e^T (Sigma_fix + s_p^2 I)^-1 e. 16.27 is the chi-square 99.9 % quantile for 3 degrees of freedom.
  // s_p, the uncertainty of the predicted antenna position in ENU, grows with the distance d the antenna
  // moved since the last accepted fix (or the alignment's start): s_p^2 = prediction_sigma_m^2 +
  // (prediction_drift_fraction d)^2. The fraction covers the odometry's drift per distance and the start's
  // yaw error (a 10 m baseline of 1 m fixes leaves ~3 deg, 5 % of the distance): without it a window
  // whose prediction drifted past the gate would reject every later fix and never come back.
  double integrity_gate = 16.27;
  double prediction_sigma_m = 1.0;
  double prediction_drift_fraction = 0.05;
  // The step guard (schedule/gnss_step_guard.h): a fix whose innovation steps away from the previous fix's
  // (multipath) is held out with the ones after it until a fix is back at the level before the step, for at
  // most this long; 0: no guard, each fix tested on its own.
  double step_max_hold_s = 30.0;

  // The yaw of the world in ENU is initialised once the antenna has moved this far horizontally (largest
  // distance from the first used position) over at least min_alignment_fixes fixes; the initial alignment
  // is refused when the residual RMS of its fixes exceeds max_alignment_rms_m.
  double min_alignment_baseline_m = 10.0;
  int min_alignment_fixes = 5;
  double max_alignment_rms_m = 10.0;

  // Placement of a fix between the window's nodes: interpolated between the two nodes around it when they
  // are at most max_interpolation_gap_s apart; a fix outside the nodes' span, or in a longer gap, is
  // attached to the nearest node if it is within max_snap_s of it, and not used otherwise.
  double max_interpolation_gap_s = 1.0;
  double max_snap_s = 0.05;

  // The noise of one status (kNoFix: the fix entry; such fixes are rejected before).
  const GnssStatusNoise& Noise(GnssFixStatus status) const;

  // Names the first bad field and its value ("lio.gnss.integrity_gate: must be > 0, got -1").
  Status Validate() const;
};

// "no_fix", "fix", "sbas", "rtk_float", "rtk_fixed".
const char* GnssStatusName(GnssFixStatus status);

}  // namespace uf::estimator
