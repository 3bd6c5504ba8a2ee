// The georeferenced trajectory files: trajectory_wgs84.csv read back and converted to ENU with the same
// EnuFrame lands within a millimetre of the input (and its orientation, taken back from the local ENU frame,
// on the input's); trajectory.geojson parses as an RFC 7946 FeatureCollection with [lon, lat, height]
// positions; errors name the file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "odometry/io/geo_trajectory_file.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

using testing::TempDir;

// A 3 km loop with climbs and turns, in the ENU frame of the origin.
Trajectory Drive(std::size_t n) {
  Trajectory trajectory;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2 * 3.14159265358979 * static_cast<double>(i) / static_cast<double>(n);
    trajectory.stamps.push_back(1'700'000'000'123'456'789 + static_cast<Stamp>(i) * 100'000'007);
    trajectory.poses.emplace_back(
        SO3::Exp(Eigen::Vector3d(0.05 * std::sin(3 * a), 0.02, a + 1.0)),
        Eigen::Vector3d(1500 * std::sin(a), 800 * (1 - std::cos(a)), 30 * std::sin(2 * a)));
  }
  return trajectory;
}

const GeodeticOrigin kOrigin{48.137154, 11.576124, 565.3};

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(GnssTrajectoryFiles, Wgs84CsvRoundTripsWithinAMillimetre) {
  TempDir dir;
  const Trajectory trajectory = Drive(200);
  auto enu = EnuFrame::Create(kOrigin);
  ASSERT_TRUE(enu);
  const std::string path = dir.File("trajectory_wgs84.csv");
  ASSERT_TRUE(WriteWgs84TrajectoryCsv(path, trajectory, *enu).ok());
  const std::vector<std::string> lines = Lines(testing::ReadText(path));
  ASSERT_EQ(lines.size(), trajectory.size() + 1);
  EXPECT_EQ(lines[0], "stamp_ns,latitude_deg,longitude_deg,height_m,qx,qy,qz,qw");
  double worst_m = 0, worst_rad = 0;
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    std::istringstream in(lines[i + 1]);
    long long stamp = 0;
    double v[7];
    char comma = 0;
    in >> stamp;
    for (double& x : v) in >> comma >> x;
    ASSERT_TRUE(in && comma == ',') << lines[i + 1];
    EXPECT_EQ(stamp, trajectory.stamps[i]);
    const Eigen::Vector3d back = enu->EnuFromGeodetic(Eigen::Vector3d(v[0], v[1], v[2]));
    worst_m = std::max(worst_m, (back - trajectory.poses[i].translation()).norm());
    // The orientation is in the local ENU frame at the position: turn it back into the origin's.
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    EXPECT_NEAR(q.norm(), 1.0, 1e-11);
    const Eigen::Matrix3d R_origin_body =
        LocalEnuFromOriginEnu(kOrigin, v[0], v[1]).transpose() * q.normalized().toRotationMatrix();
    worst_rad = std::max(worst_rad, (R_origin_body - trajectory.poses[i].so3().matrix()).norm());
  }
  EXPECT_LT(worst_m, 1e-3);
  EXPECT_LT(worst_rad, 1e-9);
}

TEST(GnssTrajectoryFiles, LocalEnuTurnsWithTheEarth) {
  // At the origin: the identity. A quarter turn east along the equator: the origin's "down" is the local
  // east, and the origin's east is the local up.
  EXPECT_LT((LocalEnuFromOriginEnu(kOrigin, kOrigin.latitude_deg, kOrigin.longitude_deg) -
             Eigen::Matrix3d::Identity())
                .norm(),
            1e-15);
  const Eigen::Matrix3d R = LocalEnuFromOriginEnu({0, 0, 0}, 0, 90);
  EXPECT_LT((R * Eigen::Vector3d(0, 0, -1) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((R * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);
}

TEST(GnssTrajectoryFiles, GeoJsonIsAFeatureCollectionOfLonLatHeight) {
  TempDir dir;
  const Trajectory trajectory = Drive(50);
  auto enu = EnuFrame::Create(kOrigin);
  ASSERT_TRUE(enu);
  const std::string path = dir.File("trajectory.geojson");
  ASSERT_TRUE(WriteTrajectoryGeoJson(path, trajectory, *enu).ok());
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(path));
  EXPECT_EQ(json.at("type"), "FeatureCollection");
  ASSERT_EQ(json.at("features").size(), 1u);
  const nlohmann::json& feature = json.at("features")[0];
  EXPECT_EQ(feature.at("type"), "Feature");
  EXPECT_EQ(feature.at("properties").at("start_stamp_ns").get<long long>(), trajectory.stamps.front());
  EXPECT_EQ(feature.at("properties").at("end_stamp_ns").get<long long>(), trajectory.stamps.back());
  EXPECT_EQ(feature.at("properties").at("poses").get<std::size_t>(), trajectory.size());
  EXPECT_EQ(feature.at("geometry").at("type"), "LineString");
  const nlohmann::json& coordinates = feature.at("geometry").at("coordinates");
  ASSERT_EQ(coordinates.size(), trajectory.size());
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    ASSERT_EQ(coordinates[i].size(), 3u);
    const double lon = coordinates[i][0], lat = coordinates[i][1], height = coordinates[i][2];
    const Eigen::Vector3d llh = enu->GeodeticFromEnu(trajectory.poses[i].translation());
    EXPECT_NEAR(lon, llh.y(), 1e-9) << i;  // longitude first (RFC 7946)
    EXPECT_NEAR(lat, llh.x(), 1e-9) << i;
    EXPECT_NEAR(height, llh.z(), 1e-5) << i;
    EXPECT_LT(
        (enu->EnuFromGeodetic(Eigen::Vector3d(lat, lon, height)) - trajectory.poses[i].translation()).norm(),
        1e-3);
  }
}

TEST(GnssTrajectoryFiles, ErrorsNameTheFile) {
  TempDir dir;
  auto enu = EnuFrame::Create(kOrigin);
  ASSERT_TRUE(enu);
  Trajectory stampless = Drive(5);
  stampless.stamps.clear();
  const std::string csv = dir.File("trajectory_wgs84.csv"), geojson = dir.File("trajectory.geojson");
  Status s = WriteWgs84TrajectoryCsv(csv, stampless, *enu);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find(csv), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("one stamp per pose"), std::string::npos) << s.message();
  s = WriteTrajectoryGeoJson(geojson, Drive(1), *enu);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("at least 2 poses"), std::string::npos) << s.message();
  Trajectory broken = Drive(5);
  broken.poses[3] = SE3(SO3(), Eigen::Vector3d(std::nan(""), 0, 0));
  s = WriteTrajectoryGeoJson(geojson, broken, *enu);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("pose 3 is not finite"), std::string::npos) << s.message();
  const std::string unwritable = dir.File("no/such/folder/trajectory_wgs84.csv");
  s = WriteWgs84TrajectoryCsv(unwritable, Drive(5), *enu);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no/such/folder"), std::string::npos) << s.message();
  // Nothing was left under the final names.
  EXPECT_FALSE(std::ifstream(csv).good());
  EXPECT_FALSE(std::ifstream(geojson).good());
  // An empty trajectory gives the header alone.
  ASSERT_TRUE(WriteWgs84TrajectoryCsv(csv, Trajectory(), *enu).ok());
  EXPECT_EQ(Lines(testing::ReadText(csv)).size(), 1u);
}

}  // namespace
}  // namespace uf
