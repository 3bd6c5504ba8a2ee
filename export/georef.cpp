#include "export/georef.h"

#include <GeographicLib/TransverseMercator.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "odometry/io/atomic_file.h"

namespace uf::exporting {

const char* OutputCrsName(OutputCrs crs) {
  switch (crs) {
    case OutputCrs::kLocal:
      return "local";
    case OutputCrs::kEnu:
      return "enu";
    case OutputCrs::kUtm:
      return "utm";
  }
  return "?";
}

Expected<Georeference> Georeference::Create(const GeodeticOrigin& origin) {
  Expected<EnuFrame> enu = EnuFrame::Create(origin);
  if (!enu) return Status::Error("georef." + enu.error());
  // UTMUPS::UTM forces a UTM zone (the standard one, with the Norway/Svalbard exceptions) even where the
  // standard choice would be UPS.
  const int zone = GeographicLib::UTMUPS::StandardZone(origin.latitude_deg, origin.longitude_deg,
                                                       GeographicLib::UTMUPS::UTM);
  return Georeference(std::move(*enu), zone, origin.latitude_deg >= 0.0);
}

int Georeference::epsg() const { return (north_ ? 32600 : 32700) + zone_; }

Eigen::Vector3d Georeference::EnuToUtm(const Eigen::Vector3d& enu) const {
  constexpr double kFalseEasting = 500e3, kFalseNorthingSouth = 10000e3;  // m, UTM definition
  const Eigen::Vector3d geodetic = enu_.GeodeticFromEnu(enu);
  double x_tm = 0, y_tm = 0;
  // Exact transverse Mercator with the UTM scale k0 = 0.9996 about the zone's central meridian; unlike
  // UTMUPS::Forward it never throws far outside the zone.
  GeographicLib::TransverseMercator::UTM().Forward(central_meridian_deg(), geodetic.x(), geodetic.y(), x_tm,
                                                   y_tm);
  return {kFalseEasting + x_tm, y_tm + (north_ ? 0.0 : kFalseNorthingSouth), geodetic.z()};
}

std::string Georeference::UtmWkt() const {
  const std::string name = "WGS 84 / UTM zone " + std::to_string(zone_) + (north_ ? "N" : "S");
  return "PROJCS[\"" + name +
         "\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
         "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
         "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],"
         "AUTHORITY[\"EPSG\",\"4326\"]],PROJECTION[\"Transverse_Mercator\"],"
         "PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\"," +
         std::to_string(6 * zone_ - 183) +
         "],PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],"
         "PARAMETER[\"false_northing\"," +
         (north_ ? "0" : "10000000") +
         "],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH],"
         "AUTHORITY[\"EPSG\",\"" +
         std::to_string(epsg()) + "\"]]";
}

Status WriteGeorefJson(const std::filesystem::path& path, const std::optional<Georeference>& georef,
                       OutputCrs crs, const Eigen::Vector3d& offset) {
  if (crs != OutputCrs::kLocal && !georef)
    return Status::Error(path.string() + ": frame " + OutputCrsName(crs) +
                         " needs a georeference (none given)");
  if (!offset.allFinite()) return Status::Error(path.string() + ": offset must be finite");
  nlohmann::ordered_json json;
  json["frame"] = OutputCrsName(crs);
  json["units"] = "metre";
  json["axes"] = crs == OutputCrs::kUtm   ? "x easting, y northing, z ellipsoidal height"
                 : crs == OutputCrs::kEnu ? "x east, y north, z up (ENU at origin)"
                                          : "x, y, z of the map frame (z up)";
  if (georef) {
    const GeodeticOrigin& origin = georef->origin();
    json["origin"] = {{"latitude_deg", origin.latitude_deg},
                      {"longitude_deg", origin.longitude_deg},
                      {"height_m", origin.height_m},
                      {"height_reference", "WGS84 ellipsoid"}};
    json["utm"] = {
        {"zone", georef->utm_zone()}, {"hemisphere", georef->north() ? "N" : "S"}, {"epsg", georef->epsg()}};
  }
  if (crs == OutputCrs::kUtm) json["crs"] = {{"epsg", georef->epsg()}, {"wkt", georef->UtmWkt()}};
  json["offset"] = {offset.x(), offset.y(), offset.z()};
  json["offset_meaning"] = "file coordinate + offset = coordinate in frame";

  AtomicFileWriter file(path.string());
  if (Status s = file.status(); !s.ok()) return s;
  file.stream() << json.dump(2) << '\n';
  return file.Commit();
}

}  // namespace uf::exporting
