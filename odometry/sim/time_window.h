// A window of true (ground-truth clock) time in which a simulated event is active: darkness, slips, outages.
#pragma once

#include "odometry/types/stamp.h"

namespace uf::sim {

struct TimeWindow {
  Stamp begin = 0;  // ns, inclusive
  Stamp end = 0;    // ns, exclusive

  bool Contains(Stamp t) const { return t >= begin && t < end; }
};

}  // namespace uf::sim
