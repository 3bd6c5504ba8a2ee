// ENU <-> WGS84 geodetic at an origin, against textbook formulas and hand-computed values (never against
// GeographicLib called directly), and the origin's validation.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "odometry/types/geodetic.h"

namespace uf {
namespace {

using Eigen::Vector3d;

// WGS84: semi-major axis a and first eccentricity squared e^2 = f (2 - f).
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kE2 = kF * (2.0 - kF);
constexpr double kDeg = std::numbers::pi / 180.0;

const std::vector<GeodeticOrigin> kOrigins = {{48.137, 11.575, 520.0},
                                              {-33.86, 151.21, 10.0},
                                              {0.0, 0.0, 0.0},
                                              {64.1, -21.9, -30.0},
                                              {-75.0, -179.5, 2800.0}};

// Prime vertical radius of curvature N = a / sqrt(1 - e^2 sin^2 phi).
double PrimeVerticalRadius(double latitude_rad) {
  return kA / std::sqrt(1.0 - kE2 * std::sin(latitude_rad) * std::sin(latitude_rad));
}

// Meridian radius of curvature M = a (1 - e^2) / (1 - e^2 sin^2 phi)^1.5.
double MeridianRadius(double latitude_rad) {
  return kA * (1.0 - kE2) / std::pow(1.0 - kE2 * std::sin(latitude_rad) * std::sin(latitude_rad), 1.5);
}

// Textbook ECEF of a geodetic point: ((N + h) cos phi cos lambda, (N + h) cos phi sin lambda,
// (N (1 - e^2) + h) sin phi).
Vector3d Ecef(const Vector3d& lat_lon_h) {
  const double phi = lat_lon_h.x() * kDeg, lambda = lat_lon_h.y() * kDeg, h = lat_lon_h.z();
  const double n = PrimeVerticalRadius(phi);
  return Vector3d((n + h) * std::cos(phi) * std::cos(lambda), (n + h) * std::cos(phi) * std::sin(lambda),
                  (n * (1.0 - kE2) + h) * std::sin(phi));
}

// An independent ENU: R_ecef_enu^T (ecef - ecef_origin), columns east, north, up at the origin.
Vector3d ReferenceEnu(const GeodeticOrigin& origin, const Vector3d& lat_lon_h) {
  const double phi = origin.latitude_deg * kDeg, lambda = origin.longitude_deg * kDeg;
  Eigen::Matrix3d R_ecef_enu;
  R_ecef_enu.col(0) << -std::sin(lambda), std::cos(lambda), 0.0;
  R_ecef_enu.col(1) << -std::sin(phi) * std::cos(lambda), -std::sin(phi) * std::sin(lambda), std::cos(phi);
  R_ecef_enu.col(2) << std::cos(phi) * std::cos(lambda), std::cos(phi) * std::sin(lambda), std::sin(phi);
  const Vector3d origin_ecef = Ecef(Vector3d(origin.latitude_deg, origin.longitude_deg, origin.height_m));
  return R_ecef_enu.transpose() * (Ecef(lat_lon_h) - origin_ecef);
}

Vector3d AsVector(const GeodeticOrigin& origin) {
  return Vector3d(origin.latitude_deg, origin.longitude_deg, origin.height_m);
}

TEST(GeodeticTest, OriginMapsToOrigin) {
  for (const GeodeticOrigin& origin : kOrigins) {
    const Vector3d lat_lon_h = GeodeticFromEnu(origin, Vector3d::Zero());
    EXPECT_NEAR(lat_lon_h.x(), origin.latitude_deg, 1e-12);
    EXPECT_NEAR(lat_lon_h.y(), origin.longitude_deg, 1e-12);
    EXPECT_NEAR(lat_lon_h.z(), origin.height_m, 1e-8);
    EXPECT_LT(EnuFromGeodetic(origin, AsVector(origin)).norm(), 1e-8);
  }
}

TEST(GeodeticTest, RoundTripOverTenKilometresIsBelowAMicrometre) {
  std::mt19937_64 engine(7);
  std::uniform_real_distribution<double> horizontal(-10000.0, 10000.0), vertical(-500.0, 2000.0);
  double worst = 0.0;
  for (const GeodeticOrigin& origin : kOrigins) {
    for (int i = 0; i < 200; ++i) {
      Vector3d enu;
      enu.x() = horizontal(engine);
      enu.y() = horizontal(engine);
      enu.z() = vertical(engine);
      worst = std::max(worst, (EnuFromGeodetic(origin, GeodeticFromEnu(origin, enu)) - enu).norm());
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(GeodeticTest, MatchesTheTextbookEcefConstruction) {
  std::mt19937_64 engine(11);
  std::uniform_real_distribution<double> angle(-0.08, 0.08), height(-100.0, 1500.0);
  for (const GeodeticOrigin& origin : kOrigins) {
    for (int i = 0; i < 50; ++i) {
      Vector3d lat_lon_h = AsVector(origin);
      lat_lon_h.x() += angle(engine);
      lat_lon_h.y() += angle(engine);
      lat_lon_h.z() = height(engine);
      if (std::abs(lat_lon_h.x()) > 90.0) continue;
      const Vector3d expected = ReferenceEnu(origin, lat_lon_h);
      EXPECT_LT((EnuFromGeodetic(origin, lat_lon_h) - expected).norm(), 1e-6) << expected.transpose();
      // And back: the geodetic point of the reference ENU is the point itself.
      const Vector3d back = GeodeticFromEnu(origin, expected);
      EXPECT_NEAR(back.x(), lat_lon_h.x(), 1e-11);
      EXPECT_NEAR(std::remainder(back.y() - lat_lon_h.y(), 360.0), 0.0, 1e-11);
      EXPECT_NEAR(back.z(), lat_lon_h.z(), 1e-6);
    }
  }
}

TEST(GeodeticTest, OneKilometreNorthIsOneKilometreOfMeridianArc) {
  const double d = 1000.0;
  for (const GeodeticOrigin& origin : kOrigins) {
    const Vector3d lat_lon_h = GeodeticFromEnu(origin, Vector3d(0.0, d, 0.0));
    const double dlat = (lat_lon_h.x() - origin.latitude_deg) * kDeg;
    // The origin sits at height h, so a small step north turns the latitude about the centre of meridian
    // curvature by d / (M + h), M at the mid latitude to second order; the tangent-plane chord of 1 km
    // differs from the arc by ~d^3 / (24 M^2) ~ 1e-6 m.
    const double mid = (origin.latitude_deg * kDeg) + 0.5 * dlat;
    EXPECT_NEAR((MeridianRadius(mid) + origin.height_m) * dlat, d, 1e-4) << origin.latitude_deg;
    // North stays in the meridian plane; the tangent plane rises above the ellipsoid by ~d^2 / (2 M).
    EXPECT_NEAR(std::remainder(lat_lon_h.y() - origin.longitude_deg, 360.0), 0.0, 1e-12);
    EXPECT_NEAR(lat_lon_h.z() - origin.height_m, d * d / (2.0 * MeridianRadius(mid)), 1e-3);
  }
}

TEST(GeodeticTest, OneKilometreEastTurnsTheLongitudeByTheParallelRadius) {
  // East is horizontal in ECEF and perpendicular to the parallel's radius (N + h) cos phi, so the longitude
  // changes by exactly atan(d / ((N + h) cos phi)).
  const double d = 1000.0;
  for (const GeodeticOrigin& origin : kOrigins) {
    const double phi = origin.latitude_deg * kDeg;
    const double parallel_radius = (PrimeVerticalRadius(phi) + origin.height_m) * std::cos(phi);
    const Vector3d lat_lon_h = GeodeticFromEnu(origin, Vector3d(d, 0.0, 0.0));
    const double dlon = std::remainder(lat_lon_h.y() - origin.longitude_deg, 360.0) * kDeg;
    EXPECT_NEAR(dlon, std::atan2(d, parallel_radius), 1e-13) << origin.latitude_deg;
  }
}

TEST(GeodeticTest, UpIsTheEllipsoidNormal) {
  for (const GeodeticOrigin& origin : kOrigins) {
    const Vector3d lat_lon_h = GeodeticFromEnu(origin, Vector3d(0.0, 0.0, 100.0));
    EXPECT_NEAR(lat_lon_h.x(), origin.latitude_deg, 1e-12);
    EXPECT_NEAR(lat_lon_h.y(), origin.longitude_deg, 1e-12);
    EXPECT_NEAR(lat_lon_h.z(), origin.height_m + 100.0, 1e-8);
  }
}

TEST(GeodeticTest, InvalidOriginsNameTheField) {
  EXPECT_TRUE(ValidateGeodeticOrigin({48.0, 11.0, 500.0}).ok());
  EXPECT_TRUE(ValidateGeodeticOrigin({-90.0, 180.0, 0.0}).ok());
  const Status latitude = ValidateGeodeticOrigin({91.0, 0.0, 0.0});
  ASSERT_FALSE(latitude.ok());
  EXPECT_EQ(latitude.message(), "origin.latitude_deg: must be in [-90, 90], got 91");
  const Status longitude = ValidateGeodeticOrigin({0.0, -180.5, 0.0});
  ASSERT_FALSE(longitude.ok());
  EXPECT_EQ(longitude.message(), "origin.longitude_deg: must be in [-180, 180], got -180.5");
  const Status height = ValidateGeodeticOrigin({0.0, 0.0, std::nan("")});
  ASSERT_FALSE(height.ok());
  EXPECT_EQ(height.message(), "origin.height_m: must be in [-12000, 100000] m, got nan");
  EXPECT_EQ(ValidateGeodeticOrigin({0.0, 0.0, 2e5}).message(),
            "origin.height_m: must be in [-12000, 100000] m, got 200000");
  // The value as it reads back, not rounded into the range.
  EXPECT_EQ(ValidateGeodeticOrigin({std::nextafter(90.0, 91.0), 0.0, 0.0}).message(),
            "origin.latitude_deg: must be in [-90, 90], got 90.00000000000001");
  EXPECT_EQ(ValidateGeodeticOrigin({std::nan(""), 0.0, 0.0}).message(),
            "origin.latitude_deg: must be in [-90, 90], got nan");
  EXPECT_TRUE(ValidateGeodeticOrigin({0.0, 0.0, -12000.0}).ok());
  EXPECT_TRUE(ValidateGeodeticOrigin({0.0, 0.0, 100000.0}).ok());
  // An EnuFrame is only made at a valid origin, with the same message.
  const Expected<EnuFrame> frame = EnuFrame::Create({0.0, 181.0, 0.0});
  ASSERT_FALSE(frame.ok());
  EXPECT_EQ(frame.error(), "origin.longitude_deg: must be in [-180, 180], got 181");
}

TEST(GeodeticTest, OneKilometreEastOnTheEquatorByHand) {
  // At latitude 0, longitude 0, height 0 the ENU frame sits at ECEF (a, 0, 0) with east = +y_ecef, so ENU
  // (1000, 0, 0) is ECEF (a, 1000, 0), in the equatorial plane: latitude 0, longitude atan(1000 / a) =
  // 1.56785593004e-4 rad (1000 m / 6378137 m = 1.56785594289e-4 rad less a^-3 1000^3 / 3 = 1.3e-12 rad),
  // height |(a, 1000)| - a = 1000^2 / (|(a, 1000)| + a) = 0.0783927967 m (~ 1000^2 / (2 a) = 0.0783927971 m),
  // to the ~1e-9 m that a double resolves at 6378 km.
  const EnuFrame frame = *EnuFrame::Create({0.0, 0.0, 0.0});
  const Vector3d lat_lon_h = frame.GeodeticFromEnu(Vector3d(1000.0, 0.0, 0.0));
  EXPECT_NEAR(lat_lon_h.x(), 0.0, 1e-12);
  EXPECT_NEAR(lat_lon_h.y() * kDeg, 1000.0 / 6378137.0, 2e-12);
  EXPECT_NEAR(lat_lon_h.y() * kDeg, 1.56785593004e-4, 1e-15);
  EXPECT_NEAR(lat_lon_h.z(), 0.0783927967, 2e-9);
  // And back.
  EXPECT_LT((frame.EnuFromGeodetic(lat_lon_h) - Vector3d(1000.0, 0.0, 0.0)).norm(), 1e-9);
}

TEST(GeodeticTest, EnuMatchesHandComputedGeodeticOffsets) {
  // Small offsets at height h: up changes only the height; east by x changes longitude by x / ((N + h)
  // cos(lat)), north by y changes latitude by y / (M + h), with N = a / w, M = a (1 - e^2) / w^3, w = sqrt(1
  // - e^2 sin^2(lat)) (radii of curvature of the prime vertical and the meridian).
  const double lat = 48.0;
  const EnuFrame frame = *EnuFrame::Create({lat, 11.0, 500.0});
  const double w = std::sqrt(1 - kE2 * std::pow(std::sin(lat * kDeg), 2));
  const double n = kA / w + 500.0, m = kA * (1 - kE2) / (w * w * w) + 500.0;
  const Vector3d up = frame.GeodeticFromEnu(Vector3d(0, 0, 25));
  EXPECT_NEAR(up.x(), lat, 1e-12);
  EXPECT_NEAR(up.y(), 11.0, 1e-12);
  EXPECT_NEAR(up.z(), 525.0, 1e-6);
  const Vector3d east = frame.GeodeticFromEnu(Vector3d(10, 0, 0));
  EXPECT_NEAR((east.y() - 11.0) * kDeg, 10 / (n * std::cos(lat * kDeg)), 1e-11);
  const Vector3d north = frame.GeodeticFromEnu(Vector3d(0, 10, 0));
  EXPECT_NEAR((north.x() - lat) * kDeg, 10 / m, 1e-11);
}

TEST(GeodeticTest, RoundTripOverThirtyFiveKilometres) {
  const EnuFrame frame = *EnuFrame::Create({-37.8, 144.96, 30.0});
  for (const Vector3d& enu :
       {Vector3d(0, 0, 0), Vector3d(1234.5, -4321.25, 17.0), Vector3d(-20e3, 35e3, -100.0)}) {
    const Vector3d back = frame.EnuFromGeodetic(frame.GeodeticFromEnu(enu));
    EXPECT_LT((back - enu).norm(), 1e-6) << enu.transpose();
  }
}

}  // namespace
}  // namespace uf
