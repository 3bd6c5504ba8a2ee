#include "odometry/estimator/schedule/gnss_step_guard.h"

#include <Eigen/Cholesky>
#include <limits>

namespace uf::estimator {

double GnssStepGuard::StepD2(const Seen& from, const Seen& to) const {
  const double moved = rule_.drift_fraction * (to.antenna - from.antenna).norm();
  const Eigen::Matrix3d S = from.covariance + to.covariance +
                            (moved * moved + rule_.jitter_m * rule_.jitter_m) * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d d = to.innovation - from.innovation;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(S);
  if (ldlt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return d.dot(ldlt.solve(d));
}

bool GnssStepGuard::Admit(Stamp stamp, const Eigen::Vector3d& innovation, const Eigen::Matrix3d& covariance,
                          const Eigen::Vector3d& antenna,
                          const std::optional<Eigen::Vector3d>& previous_now) {
  const Seen seen{stamp, innovation, antenna, covariance};
  if (!(rule_.max_hold_s > 0) || !innovation.allFinite() || !covariance.allFinite() || !antenna.allFinite()) {
    last_step_d2_ = 0;
    return true;
  }
  bool admit = true;
  if (hold_) {
    last_step_d2_ = StepD2(*hold_, seen);
    if (last_step_d2_ <= rule_.gate || ToSeconds(stamp - hold_start_) > rule_.max_hold_s)
      hold_.reset();  // back at the level before the step, or held long enough
    else
      admit = false;
  } else if (previous_ && ToSeconds(stamp - previous_->stamp) <= rule_.max_gap_s) {
    if (previous_now && previous_now->allFinite()) previous_->innovation = *previous_now;
    last_step_d2_ = StepD2(*previous_, seen);
    if (last_step_d2_ > rule_.gate) {
      hold_ = previous_;
      hold_start_ = stamp;
      admit = false;
    }
  } else {
    last_step_d2_ = 0;
  }
  previous_ = seen;
  return admit;
}

void GnssStepGuard::Reset() {
  previous_.reset();
  hold_.reset();
  last_step_d2_ = 0;
}

}  // namespace uf::estimator
