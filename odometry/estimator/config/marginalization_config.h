// Configuration of the marginalization of the window's oldest states (marginalization.h): where eigenvalues
// count as zero.
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

struct MarginalizationConfig {
  // Eigenvalues of H_mm and of H* at or below max(eigenvalue_threshold, relative_eigenvalue_threshold *
  // largest eigenvalue) are treated as zero (unobserved directions): dropped from the pseudo-inverse and
  // from the prior's rows. Absolute part in information units (1 / tangent unit^2), VINS-Mono uses 1e-8;
  // the relative part guards against round-off of large information (double epsilon ~ 2e-16).
  double eigenvalue_threshold = 1e-8;
  double relative_eigenvalue_threshold = 1e-12;

  // Returns an error naming the field and value, e.g. "marginalization.eigenvalue_threshold: must be >= 0".
  Status Validate() const;
};

}  // namespace uf::estimator
