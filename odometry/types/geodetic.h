// A place on the Earth and the local east-north-up (ENU) tangent frame there: a WGS84 geodetic origin
// (latitude, longitude, ellipsoidal height), its validation, and the exact conversions between ENU
// coordinates and geodetic ones (no flat-earth approximation). Both go through earth-centred earth-fixed
// (ECEF) coordinates, p_ecef = p0_ecef + R_ecef_enu * enu, with R_ecef_enu's columns the east, north and up
// unit vectors at the origin (up = the ellipsoid normal there). The simulator's world, the georeference of
// maps and exports, and the GNSS alignment all use this one type (docs/ARCHITECTURE.md, "Frames and time").
// GeographicLib (LocalCartesian on the WGS84 ellipsoid) does the work; it stays out of this header.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "odometry/types/status.h"

namespace uf {

// The geodetic point at which an ENU frame's origin sits (x east, y north, z up along the normal).
struct GeodeticOrigin {
  double latitude_deg = 0.0;   // degrees, north positive, in [-90, 90]
  double longitude_deg = 0.0;  // degrees, east positive, in [-180, 180]
  double height_m = 0.0;       // m above the WGS84 ellipsoid (not above mean sea level), in [-12 km, 100 km]
};

// Fails, naming the field and value ("origin.latitude_deg: must be in [-90, 90], got 91"), for an origin
// outside the ranges above or with a non-finite value.
Status ValidateGeodeticOrigin(const GeodeticOrigin& origin);

// The ENU frame at a valid origin. Cheap to copy (the GeographicLib state is shared and never changes).
class EnuFrame {
 public:
  // Fails as ValidateGeodeticOrigin does.
  static Expected<EnuFrame> Create(const GeodeticOrigin& origin);

  const GeodeticOrigin& origin() const { return origin_; }

  // (latitude deg, longitude deg, ellipsoidal height m) of the ENU point `enu` (m). Longitude is returned in
  // [-180, 180].
  Eigen::Vector3d GeodeticFromEnu(const Eigen::Vector3d& enu) const;
  // ENU coordinates (m) of the geodetic point (latitude deg, longitude deg, height m); the inverse.
  Eigen::Vector3d EnuFromGeodetic(const Eigen::Vector3d& lat_lon_h) const;

 private:
  struct Impl;  // GeographicLib's LocalCartesian
  EnuFrame(const GeodeticOrigin& origin, std::shared_ptr<const Impl> impl);

  GeodeticOrigin origin_;
  std::shared_ptr<const Impl> impl_;
};

// One-off conversions through EnuFrame at `origin`; assert a valid origin.
Eigen::Vector3d GeodeticFromEnu(const GeodeticOrigin& origin, const Eigen::Vector3d& enu);
Eigen::Vector3d EnuFromGeodetic(const GeodeticOrigin& origin, const Eigen::Vector3d& lat_lon_h);

}  // namespace uf
