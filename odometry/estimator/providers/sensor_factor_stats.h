// What the optional factors did over a run so far, as the windows that use the providers report it.
#pragma once

namespace uf::estimator {

// Factors added, and skipped (no data over the interval, or rejected by an integrity check).
struct FactorCount {
  int added = 0, skipped = 0;
};
struct SensorFactorStats {
  FactorCount wheel;
  double wheel_scale = 1;  // the estimated wheel scale (1 without wheel factors or with it fixed)
};

}  // namespace uf::estimator
