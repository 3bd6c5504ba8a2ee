// Writers of the georeferenced trajectory files (geo_trajectory_file.h).
#include <cmath>
#include <cstdio>

#include "odometry/io/atomic_file.h"
#include "odometry/io/geo_trajectory_file.h"

namespace uf {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

Eigen::Matrix3d EcefFromEnu(double latitude_deg, double longitude_deg) {
  const double sp = std::sin(latitude_deg * kDegree), cp = std::cos(latitude_deg * kDegree);
  const double sl = std::sin(longitude_deg * kDegree), cl = std::cos(longitude_deg * kDegree);
  Eigen::Matrix3d R;            // columns: east, north, up
  R << -sl, -sp * cl, cp * cl,  //
      cl, -sp * sl, cp * sl,    //
      0, cp, sp;
  return R;
}

Status CheckTrajectory(const std::string& path, const Trajectory& trajectory, std::size_t min_poses) {
  if (trajectory.stamps.size() != trajectory.size())
    return Status::Error(path + ": the trajectory needs one stamp per pose, has " +
                         std::to_string(trajectory.stamps.size()) + " for " +
                         std::to_string(trajectory.size()) + " poses");
  if (trajectory.size() < min_poses)
    return Status::Error(path + ": a LineString needs at least " + std::to_string(min_poses) +
                         " poses, got " + std::to_string(trajectory.size()));
  for (std::size_t i = 0; i < trajectory.size(); ++i)
    if (!trajectory.poses[i].translation().allFinite() || !trajectory.poses[i].so3().matrix().allFinite())
      return Status::Error(path + ": pose " + std::to_string(i) + " is not finite");
  return {};
}

}  // namespace

Eigen::Matrix3d LocalEnuFromOriginEnu(const GeodeticOrigin& origin, double latitude_deg,
                                      double longitude_deg) {
  return EcefFromEnu(latitude_deg, longitude_deg).transpose() *
         EcefFromEnu(origin.latitude_deg, origin.longitude_deg);
}

Status WriteWgs84TrajectoryCsv(const std::string& path, const Trajectory& trajectory_enu,
                               const EnuFrame& enu) {
  if (Status s = CheckTrajectory(path, trajectory_enu, 0); !s.ok()) return s;
  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  std::ofstream& out = file.stream();
  out << "stamp_ns,latitude_deg,longitude_deg,height_m,qx,qy,qz,qw\n";
  char line[256];
  for (std::size_t i = 0; i < trajectory_enu.size(); ++i) {
    const SE3& pose = trajectory_enu.poses[i];
    const Eigen::Vector3d llh = enu.GeodeticFromEnu(pose.translation());
    const SO3 R_local_body(LocalEnuFromOriginEnu(enu.origin(), llh.x(), llh.y()) * pose.so3().matrix());
    const Eigen::Quaterniond q = R_local_body.quaternion();
    std::snprintf(line, sizeof(line), "%lld,%.10f,%.10f,%.6f,%.12f,%.12f,%.12f,%.12f\n",
                  static_cast<long long>(trajectory_enu.stamps[i]), llh.x(), llh.y(), llh.z(), q.x(), q.y(),
                  q.z(), q.w());
    out << line;
  }
  return file.Commit();
}

Status WriteTrajectoryGeoJson(const std::string& path, const Trajectory& trajectory_enu,
                              const EnuFrame& enu) {
  if (Status s = CheckTrajectory(path, trajectory_enu, 2); !s.ok()) return s;
  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  std::ofstream& out = file.stream();
  out << "{\"type\": \"FeatureCollection\", \"features\": [{\"type\": \"Feature\",\n"
      << "\"properties\": {\"start_stamp_ns\": " << trajectory_enu.stamps.front()
      << ", \"end_stamp_ns\": " << trajectory_enu.stamps.back() << ", \"poses\": " << trajectory_enu.size()
      << "},\n\"geometry\": {\"type\": \"LineString\", \"coordinates\": [\n";
  char position[128];
  for (std::size_t i = 0; i < trajectory_enu.size(); ++i) {
    const Eigen::Vector3d llh = enu.GeodeticFromEnu(trajectory_enu.poses[i].translation());
    std::snprintf(position, sizeof(position), "[%.10f, %.10f, %.6f]%s\n", llh.y(), llh.x(), llh.z(),
                  i + 1 < trajectory_enu.size() ? "," : "");
    out << position;
  }
  out << "]}}]}\n";
  return file.Commit();
}

}  // namespace uf
