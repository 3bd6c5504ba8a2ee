// Georeference against published or hand-checkable values (never against GeographicLib called directly).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "export/georef.h"
#include "export_test_util.h"

namespace uf::exporting {
namespace {

Georeference Make(double lat, double lon, double h = 0) {
  Expected<Georeference> g = Georeference::Create({lat, lon, h});
  EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error());
  return g.value();
}

double Dms(double d, double m, double s) { return d + m / 60 + s / 3600; }

TEST(Georef, EquatorOnCentralMeridianIsFalseEastingAndZeroNorthing) {
  // lon 3 deg is the central meridian of zone 31 (6 * 31 - 183); on the equator the northing is 0.
  const Georeference g = Make(0.0, 3.0);
  EXPECT_EQ(g.utm_zone(), 31);
  EXPECT_TRUE(g.north());
  EXPECT_EQ(g.epsg(), 32631);
  const Eigen::Vector3d utm = g.EnuToUtm(Eigen::Vector3d::Zero());
  EXPECT_NEAR(utm.x(), 500000.0, 1e-6);
  EXPECT_NEAR(utm.y(), 0.0, 1e-6);
  EXPECT_NEAR(utm.z(), 0.0, 1e-6);
}

TEST(Georef, MatchesPublishedUtmCoordinates) {
  // GeographicLib's GeoConvert(1) manual lists "33.3 44.4" and "38n 444140.54 3684706.36" as the same point.
  const Georeference baghdad = Make(33.3, 44.4);
  EXPECT_EQ(baghdad.utm_zone(), 38);
  const Eigen::Vector3d a = baghdad.EnuToUtm(Eigen::Vector3d::Zero());
  EXPECT_NEAR(a.x(), 444140.54, 0.006);
  EXPECT_NEAR(a.y(), 3684706.36, 0.006);
  // AGI STK's Convert MapGridPoint example: lat 33.5 lon 74.75 -> 43S 476779 3706747 (metres).
  const Georeference kashmir = Make(33.5, 74.75);
  EXPECT_EQ(kashmir.utm_zone(), 43);
  const Eigen::Vector3d b = kashmir.EnuToUtm(Eigen::Vector3d::Zero());
  EXPECT_NEAR(b.x(), 476779.0, 0.5);
  EXPECT_NEAR(b.y(), 3706747.0, 0.5);
  // Southern hemisphere (CoordConverterJS example, SIRGAS2000 = GRS80, within 0.1 mm of WGS84 here):
  // 10d10'52.14396"S 48d20'16.79136"W -> zone 22 S, 791679.526 E, 8873360.353 N.
  const Georeference brazil = Make(-Dms(10, 10, 52.14396), -Dms(48, 20, 16.79136));
  EXPECT_EQ(brazil.utm_zone(), 22);
  EXPECT_FALSE(brazil.north());
  EXPECT_EQ(brazil.epsg(), 32722);
  const Eigen::Vector3d c = brazil.EnuToUtm(Eigen::Vector3d::Zero());
  EXPECT_NEAR(c.x(), 791679.526, 0.005);
  EXPECT_NEAR(c.y(), 8873360.353, 0.005);
}

TEST(Georef, ZoneExceptionsOfNorwayAndSvalbard) {
  EXPECT_EQ(Make(45.0, 5.0).utm_zone(), 31);   // standard: floor((5 + 180) / 6) + 1
  EXPECT_EQ(Make(60.0, 5.0).utm_zone(), 32);   // 32V is widened west over Norway
  EXPECT_EQ(Make(78.0, 10.0).utm_zone(), 33);  // Svalbard: 33X covers 9..21 E
  EXPECT_EQ(Make(-33.9, 18.4).utm_zone(), 34);
}

TEST(Georef, NorthAlongCentralMeridianScalesByK0) {
  // On the central meridian the easting stays 500000 and the northing grows by k0 = 0.9996 times the
  // meridian distance; the ellipsoid falls away below the ENU plane by d^2 / (2 R) (~0.08 m at 1 km).
  const Georeference g = Make(45.0, 3.0);
  const Eigen::Vector3d o = g.EnuToUtm(Eigen::Vector3d::Zero());
  const Eigen::Vector3d p = g.EnuToUtm(Eigen::Vector3d(0, 1000, 0));
  EXPECT_NEAR(p.x(), 500000.0, 1e-6);
  EXPECT_NEAR(p.y() - o.y(), 0.9996 * 1000.0, 0.005);
  EXPECT_NEAR(p.z(), 1000.0 * 1000.0 / (2 * 6.37e6), 0.003);
}

TEST(Georef, HemisphereStaysThatOfTheOriginAcrossTheEquator) {
  // A northern-hemisphere map: a point 1 km south of an origin 100 m north of the equator has a negative
  // northing (EPSG:326zz extended), not one near 10000 km.
  const Georeference g = Make(100.0 / 110574.0, 3.0);
  EXPECT_TRUE(g.north());
  EXPECT_NEAR(g.EnuToUtm(Eigen::Vector3d(0, -1000, 0)).y(), -0.9996 * 900.0, 0.05);
  // A southern-hemisphere map: false northing 10000 km on both sides.
  const Georeference s = Make(-100.0 / 110574.0, 3.0);
  EXPECT_FALSE(s.north());
  EXPECT_NEAR(s.EnuToUtm(Eigen::Vector3d(0, 1000, 0)).y(), 10000e3 + 0.9996 * 900.0, 0.05);
}

TEST(Georef, RejectsInvalidOriginsNamingTheField) {
  // The origin's validation (odometry/types/geodetic.h), its message prefixed with georef.
  Expected<Georeference> lat = Georeference::Create({91.0, 0.0, 0.0});
  ASSERT_FALSE(lat.ok());
  EXPECT_EQ(lat.error(), "georef.origin.latitude_deg: must be in [-90, 90], got 91");
  Expected<Georeference> lon = Georeference::Create({0.0, -181.0, 0.0});
  ASSERT_FALSE(lon.ok());
  EXPECT_NE(lon.error().find("longitude_deg"), std::string::npos);
  EXPECT_FALSE(Georeference::Create({0.0, 0.0, std::nan("")}).ok());
}

TEST(Georef, UtmWktNamesZoneAndEpsg) {
  const std::string wkt = Make(-33.9, 18.4).UtmWkt();
  EXPECT_EQ(wkt.rfind("PROJCS[\"WGS 84 / UTM zone 34S\"", 0), 0u);
  EXPECT_NE(wkt.find("PARAMETER[\"central_meridian\",21]"), std::string::npos);
  EXPECT_NE(wkt.find("PARAMETER[\"false_northing\",10000000]"), std::string::npos);
  EXPECT_NE(wkt.find("AUTHORITY[\"EPSG\",\"32734\"]]"), std::string::npos);
  // Balanced brackets.
  int depth = 0;
  for (char c : wkt) {
    depth += c == '[' ? 1 : c == ']' ? -1 : 0;
    ASSERT_GE(depth, 0);
  }
  EXPECT_EQ(depth, 0);
}

TEST(Georef, JsonSidecarStatesFrameOriginZoneAndOffset) {
  test::ScratchDir dir;
  const Georeference g = Make(33.3, 44.4, 35.5);
  ASSERT_TRUE(
      WriteGeorefJson(dir / "georef.json", g, OutputCrs::kUtm, Eigen::Vector3d(444000, 3684000, 0)).ok());
  std::ifstream in(dir / "georef.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["frame"], "utm");
  EXPECT_EQ(j["units"], "metre");
  EXPECT_EQ(j["origin"]["latitude_deg"], 33.3);
  EXPECT_EQ(j["origin"]["longitude_deg"], 44.4);
  EXPECT_EQ(j["origin"]["height_m"], 35.5);
  EXPECT_EQ(j["utm"]["zone"], 38);
  EXPECT_EQ(j["utm"]["hemisphere"], "N");
  EXPECT_EQ(j["utm"]["epsg"], 32638);
  EXPECT_EQ(j["crs"]["epsg"], 32638);
  EXPECT_EQ(j["offset"][0], 444000.0);
  EXPECT_EQ(j["offset"][1], 3684000.0);
  EXPECT_EQ(dir.Entries().size(), 1u);  // no temporary left

  ASSERT_TRUE(WriteGeorefJson(dir / "local.json", std::nullopt, OutputCrs::kLocal).ok());
  std::ifstream local_in(dir / "local.json");
  const nlohmann::json local = nlohmann::json::parse(local_in);
  EXPECT_EQ(local["frame"], "local");
  EXPECT_FALSE(local.contains("origin"));

  const Status no_georef = WriteGeorefJson(dir / "enu.json", std::nullopt, OutputCrs::kEnu);
  EXPECT_FALSE(no_georef.ok());
  EXPECT_FALSE(std::filesystem::exists(dir / "enu.json"));
}

}  // namespace
}  // namespace uf::exporting
