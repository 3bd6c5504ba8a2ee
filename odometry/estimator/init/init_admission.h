// The admission check of an initialization (docs/METHOD.md "Observability-aware initialization"; the paper's
// consistency check before pi_boot = 1): a state from S or M starts LIO only when it explains the window.
//
// In order:
// 1. M only, well-posedness: the predicted standard deviation of the gravity direction <= max_tilt_sigma_deg;
//    else deferred (not a failure: the window is still too short for the LO noise).
// 2. gravity norm: ||g| - gravity| <= max_gravity_error gravity, |g| the mean specific force (S) or the free
//    MAP estimate (M); else rejected.
// 3. consistency: the velocity changes the IMU measured against those of the admitted state (velocities v_k
//    at the scans' middles, the gravity-aligned LO attitudes R_k, the biases; preintegrations re-integrated
//    at those biases), per interval
//      r_v = R_k^T (v_k+1 - v_k - g T) - dv,
//    whitened by the preintegration's covariance of dv: chi2 = sum r_v^T Sigma^-1 r_v over 3 n values, less
//    the gravity direction fitted to them (2). Rejected when chi2 / dof > max_chi2_per_dof. A wrong gravity
//    shows here: a tilt error e leaves g e T per interval (0.034 m/s per 0.1 s at 2 deg, against 0.006 m/s of
//    IMU noise at the default densities), and so does a wrong velocity. The position residuals are not part
//    of it: their noise is the LO's, which is not known in advance (2-4 mm between scans in the simulated
//    streets, 1-4 cm on the rough wild terrain); S's speed test and M's a posteriori noise factor use them.
// 4. M only, settled (CheckGravitySettled): the newest scan moved the gravity direction by at most
//    max_tilt_sigma_deg from the previous attempt's estimate (one scan less); else deferred.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/init/inertial_alignment.h"
#include "odometry/estimator/init/init_mode_selection.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

struct AdmissionCheck {
  enum class Verdict { kAdmitted, kDeferred, kRejected };
  Verdict verdict = Verdict::kRejected;
  double chi2_per_dof = 0;  // of step 3, when it ran
  int dof = 0;
  std::string reason;  // why deferred or rejected; "" when admitted
};

// mode is S or M; poses[k] = T_lo_imu of node k, preintegrations[k] between nodes k and k + 1 (any
// linearization bias).
AdmissionCheck CheckAdmission(InitMode mode, const InertialAlignment& alignment, std::span<const SE3> poses,
                              std::vector<ImuPreintegration> preintegrations,
                              const InertialInitConfig& config, double gravity);

// The direction of gravity in "lo" that an alignment estimates (a unit vector, "down").
Eigen::Vector3d GravityDirectionLo(const InertialAlignment& alignment);

// Step 4, on a check CheckAdmission admitted for M: deferred unless `before` (the previous attempt's
// GravityDirectionLo, none when it made no estimate) lies within max_tilt_sigma_deg of `now`. M's predicted
// sigma takes the LO's position errors for white; they are correlated from scan to scan, and an estimate
// that one scan more still moves by more than that sigma is not done (simulated moving starts: estimates
// admitted at a sigma of 0.23 deg and 0.8-0.9 deg off had moved by 0.46 deg with their last scan). When the
// model holds, nested estimates differ by sqrt(sigma_before^2 - sigma_now^2), about 0.14 deg there.
void CheckGravitySettled(const std::optional<Eigen::Vector3d>& before, const Eigen::Vector3d& now,
                         const InertialInitConfig& config, AdmissionCheck& check);

}  // namespace uf::estimator
