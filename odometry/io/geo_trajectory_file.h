// Georeferenced trajectory files, from a trajectory in an ENU frame (T_enu_body per stamp) and that frame's
// geodetic origin (odometry/types/geodetic.h: exact conversions through ECEF; heights are ellipsoidal,
// above WGS84, not above mean sea level). Written under a temporary name and renamed into place; errors
// name the file.
//
// trajectory_wgs84.csv: a header line, then one line per pose:
//   stamp_ns,latitude_deg,longitude_deg,height_m,qx,qy,qz,qw
// degrees with 10 decimals (1e-10 deg, about 10 um), height with 6, the quaternion with 12. The quaternion
// is the body's orientation in the local ENU frame at that position (east, north, up of the ellipsoid
// there), so that it means the same wherever the pose is; it differs from the orientation in the origin's
// ENU frame by the turn of the tangent plane, about 1 deg per 111 km from the origin.
//
// trajectory.geojson (RFC 7946): a FeatureCollection with one Feature whose geometry is a LineString of
// [longitude, latitude, height] positions (that order, degrees and m), with properties start_stamp_ns,
// end_stamp_ns (integers) and poses (the count). A LineString needs at least two poses.
#pragma once

#include <string>

#include "odometry/types/geodetic.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

// Both need stamps (one per pose) and finite poses.
Status WriteWgs84TrajectoryCsv(const std::string& path, const Trajectory& trajectory_enu,
                               const EnuFrame& enu);
Status WriteTrajectoryGeoJson(const std::string& path, const Trajectory& trajectory_enu, const EnuFrame& enu);

// The rotation from the ENU frame at `origin` to the local ENU frame at (latitude, longitude) (degrees):
// R_local_origin = R_ecef_enu(latitude, longitude)^T R_ecef_enu(origin), with R_ecef_enu's columns the
// east, north and up (ellipsoid normal) unit vectors.
Eigen::Matrix3d LocalEnuFromOriginEnu(const GeodeticOrigin& origin, double latitude_deg,
                                      double longitude_deg);

}  // namespace uf
