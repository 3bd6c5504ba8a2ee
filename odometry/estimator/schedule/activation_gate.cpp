#include "odometry/estimator/schedule/activation_gate.h"

namespace uf::estimator {

bool ActivationGate::Update(double score, int count) {
  const bool enough = count >= rule_.min_count;
  if (active_) {
    // A NaN score fails the comparison: not trusted.
    if (!(score <= rule_.threshold) || !enough) {
      active_ = false;
      calm_ = 0;
    }
    return active_;
  }
  calm_ = (score <= rule_.threshold - rule_.release_margin && enough) ? calm_ + 1 : 0;
  if (calm_ >= rule_.release_keyframes) active_ = true;
  return active_;
}

}  // namespace uf::estimator
