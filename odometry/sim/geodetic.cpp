#include "odometry/sim/geodetic.h"

#include <GeographicLib/LocalCartesian.hpp>
#include <cassert>
#include <cmath>
#include <sstream>
#include <string>

#include "odometry/sim/sampling.h"

namespace uf::sim {
namespace {

// The ENU frame at the origin on the WGS84 ellipsoid (GeographicLib's default).
GeographicLib::LocalCartesian EnuFrame(const GeodeticOrigin& origin) {
  assert(ValidateGeodeticOrigin(origin).ok());
  return GeographicLib::LocalCartesian(origin.latitude_deg, origin.longitude_deg, origin.altitude_m);
}

}  // namespace

Status ValidateGeodeticOrigin(const GeodeticOrigin& origin) {
  if (!std::isfinite(origin.latitude_deg) || std::abs(origin.latitude_deg) > 90.0) {
    return Status::Error("origin.latitude_deg: must be in [-90, 90], got " + NumberText(origin.latitude_deg));
  }
  if (!std::isfinite(origin.longitude_deg) || std::abs(origin.longitude_deg) > 180.0) {
    return Status::Error("origin.longitude_deg: must be in [-180, 180], got " +
                         NumberText(origin.longitude_deg));
  }
  if (!std::isfinite(origin.altitude_m)) {
    return Status::Error("origin.altitude_m: must be finite, got " + NumberText(origin.altitude_m));
  }
  return Status();
}

Eigen::Vector3d GeodeticFromEnu(const GeodeticOrigin& origin, const Eigen::Vector3d& enu) {
  Eigen::Vector3d lat_lon_h;
  EnuFrame(origin).Reverse(enu.x(), enu.y(), enu.z(), lat_lon_h.x(), lat_lon_h.y(), lat_lon_h.z());
  return lat_lon_h;
}

Eigen::Vector3d EnuFromGeodetic(const GeodeticOrigin& origin, const Eigen::Vector3d& lat_lon_h) {
  Eigen::Vector3d enu;
  EnuFrame(origin).Forward(lat_lon_h.x(), lat_lon_h.y(), lat_lon_h.z(), enu.x(), enu.y(), enu.z());
  return enu;
}

}  // namespace uf::sim
