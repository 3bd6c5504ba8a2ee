// Where a run's world frame sits on the Earth: the ENU frame at a geodetic origin (geodetic.h) and the rigid
// transform from the world into it (p_enu = T_enu_world p_world).
#pragma once

#include "odometry/types/geodetic.h"
#include "odometry/types/se3.h"

namespace uf {

struct Georeference {
  GeodeticOrigin origin;
  SE3 T_enu_world;
};

}  // namespace uf
