// Georeference of the map: the map frame is east-north-up (ENU, x east, y north, z up) at a WGS84 origin
// (latitude, longitude, ellipsoidal height). ENU <-> geodetic is odometry/types/geodetic.h's EnuFrame; the
// UTM coordinates go through GeographicLib's exact transverse Mercator (TransverseMercator::UTM, the
// projection UTMUPS uses) in the standard zone of the origin (UTMUPS::StandardZone, Norway/Svalbard
// exceptions included).
//
// Conventions:
//  - The UTM zone and hemisphere are those of the origin, for every point of the map, so a map that crosses
//    a zone boundary or the equator stays in one consistent grid (northing < 0 south of the equator in a
//    northern-hemisphere map, as EPSG:326zz extended beyond its area of use). Origins outside 80S..84N
//    (where UTM gives way to UPS) still get the UTM zone of their longitude; UPS is not supported.
//  - Heights stay ellipsoidal (WGS84) in every output frame; there is no geoid model.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "odometry/types/geodetic.h"
#include "odometry/types/status.h"

namespace uf::exporting {

// The frame coordinates are written in. kLocal: the map frame, no georeference claimed. kEnu: the map frame,
// stated to be ENU at the georeference origin. kUtm: easting, northing (WGS 84 / UTM zone of the origin) and
// ellipsoidal height.
enum class OutputCrs { kLocal, kEnu, kUtm };

const char* OutputCrsName(OutputCrs crs);  // "local" | "enu" | "utm"

class Georeference {
 public:
  // Fails for an invalid origin (ValidateGeodeticOrigin, the message prefixed "georef.").
  static Expected<Georeference> Create(const GeodeticOrigin& origin);

  const GeodeticOrigin& origin() const { return enu_.origin(); }
  int utm_zone() const { return zone_; }  // 1..60
  bool north() const { return north_; }   // hemisphere of the origin
  int epsg() const;                       // 32600 + zone (north) or 32700 + zone (south)
  double central_meridian_deg() const { return 6.0 * zone_ - 183.0; }

  // ENU -> (easting, northing, ellipsoidal height) in the origin's zone and hemisphere:
  //   E = 500000 + x_tm, N = y_tm (+ 10000000 in a southern-hemisphere map), (x_tm, y_tm) the transverse
  //   Mercator (scale 0.9996 on the central meridian) of the point's latitude and longitude.
  Eigen::Vector3d EnuToUtm(const Eigen::Vector3d& enu) const;

  // OGC WKT1 of "WGS 84 / UTM zone <zone><N|S>" (EPSG:326zz / 327zz), as GDAL writes it.
  std::string UtmWkt() const;

 private:
  Georeference(EnuFrame enu, int zone, bool north) : enu_(std::move(enu)), zone_(zone), north_(north) {}

  EnuFrame enu_;  // ENU (map frame) <-> geodetic at the origin
  int zone_ = 0;
  bool north_ = true;
};

// Writes the georef.json sidecar (atomically): {"frame": "local"|"enu"|"utm", "units": "metre",
// "axes": ..., "origin": {latitude_deg, longitude_deg, height_m, height_reference}, "utm": {zone,
// hemisphere, epsg}, "crs": {"epsg", "wkt"} (utm frame only), "offset": [x, y, z]}. `offset` is what was
// subtracted from the coordinates in the exported files (file coordinate + offset = coordinate in `frame`).
// "origin" and "utm" are present whenever `georef` is. Fails for an enu/utm frame without a georeference,
// a non-finite offset, or an unwritable path.
Status WriteGeorefJson(const std::filesystem::path& path, const std::optional<Georeference>& georef,
                       OutputCrs crs, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());

}  // namespace uf::exporting
