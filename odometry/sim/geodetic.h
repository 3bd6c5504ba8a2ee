// The simulator's world frame on the Earth: world = local east-north-up (ENU) tangent frame at a geodetic
// origin, and conversions between ENU coordinates and WGS84 geodetic latitude, longitude and ellipsoidal
// height. Exact (no flat-earth approximation): both go through earth-centred earth-fixed (ECEF)
// coordinates, p_ecef = p0_ecef + R_ecef_enu * enu, with R_ecef_enu's columns the east, north and up unit
// vectors at the origin (up = the ellipsoid normal there). GeographicLib (LocalCartesian) does the work;
// it stays out of this header.
#pragma once

#include <Eigen/Core>

#include "odometry/types/status.h"

namespace uf::sim {

// The geodetic point at which the world frame's origin sits (x east, y north, z up along the normal).
struct GeodeticOrigin {
  double latitude_deg = 0.0;   // degrees, north positive, in [-90, 90]
  double longitude_deg = 0.0;  // degrees, east positive, in [-180, 180]
  double altitude_m = 0.0;     // m above the WGS84 ellipsoid, finite
};

// Fails, naming the field and value ("origin.latitude_deg: must be in [-90, 90], got 91"), for an origin
// outside the ranges above or with a non-finite value.
Status ValidateGeodeticOrigin(const GeodeticOrigin& origin);

// (latitude deg, longitude deg, ellipsoidal height m) of the ENU point `enu` (m); asserts a valid origin.
// Longitude is returned in [-180, 180].
Eigen::Vector3d GeodeticFromEnu(const GeodeticOrigin& origin, const Eigen::Vector3d& enu);

// ENU coordinates (m) of the geodetic point (latitude deg, longitude deg, height m); the inverse of the
// above. Asserts a valid origin.
Eigen::Vector3d EnuFromGeodetic(const GeodeticOrigin& origin, const Eigen::Vector3d& lat_lon_h);

}  // namespace uf::sim
