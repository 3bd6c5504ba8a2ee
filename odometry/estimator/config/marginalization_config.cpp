#include "odometry/estimator/config/marginalization_config.h"

#include <cmath>
#include <string>

namespace uf::estimator {

Status MarginalizationConfig::Validate() const {
  if (!(eigenvalue_threshold >= 0.0) || !std::isfinite(eigenvalue_threshold)) {
    return Status::Error("marginalization.eigenvalue_threshold: must be finite and >= 0, got " +
                         std::to_string(eigenvalue_threshold));
  }
  if (!(relative_eigenvalue_threshold >= 0.0 && relative_eigenvalue_threshold < 1.0)) {
    return Status::Error("marginalization.relative_eigenvalue_threshold: must be in [0, 1), got " +
                         std::to_string(relative_eigenvalue_threshold));
  }
  return Status();
}

}  // namespace uf::estimator
