// What the optional factors did over a run so far, as the windows that use the providers report it.
#pragma once

#include <string>

namespace uf::estimator {

// Factors added, measurements skipped (bad values, no data over the interval, no node near), and rejected
// by an integrity check.
struct FactorCount {
  int added = 0, skipped = 0, rejected = 0;
};
struct SensorFactorStats {
  FactorCount wheel;
  double wheel_scale = 1;  // the estimated wheel scale (1 without wheel factors or with it fixed)
  FactorCount gnss;
  int gnss_horizontal_only = 0;  // of gnss.added: used without their height (it failed the innovation test)
  std::string gnss_alignment;    // how the world -> ENU alignment started, or why not yet ("" without GNSS)
};

}  // namespace uf::estimator
