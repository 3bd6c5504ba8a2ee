// Writers of TUM, KITTI and EuRoC trajectory files. Stamps are written exactly (nine decimals of seconds, or
// integer nanoseconds); positions with nanometre and quaternions with 1e-12 resolution.
#include <cstdio>

#include "odometry/io/atomic_file.h"
#include "odometry/io/trajectory_file.h"

namespace uf {
namespace {

Status CheckStamps(const std::string& path, const Trajectory& trajectory, const char* format) {
  if (trajectory.has_stamps() && trajectory.stamps.size() != trajectory.size())
    return Status::Error(path + ": trajectory has " + std::to_string(trajectory.stamps.size()) +
                         " stamps for " + std::to_string(trajectory.size()) + " poses");
  if (!trajectory.has_stamps() && format != nullptr)
    return Status::Error(path + ": the " + std::string(format) +
                         " format needs stamps; this trajectory has none");
  return {};
}

template <typename WriteLine>
Status WriteLines(const std::string& path, const Trajectory& trajectory, const char* header, WriteLine line) {
  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  std::ofstream& out = file.stream();
  if (header) out << header;
  char buffer[512];
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    line(buffer, sizeof(buffer), i);
    out << buffer;
  }
  return file.Commit();
}

}  // namespace

Status WriteTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  if (Status s = CheckStamps(path, trajectory, "TUM"); !s.ok()) return s;
  return WriteLines(path, trajectory, "# timestamp tx ty tz qx qy qz qw\n",
                    [&](char* b, std::size_t n, std::size_t i) {
                      const Eigen::Vector3d& t = trajectory.poses[i].translation();
                      const Eigen::Quaterniond q = trajectory.poses[i].so3().quaternion();
                      std::snprintf(b, n, "%s %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n",
                                    FormatSeconds(trajectory.stamps[i]).c_str(), t.x(), t.y(), t.z(), q.x(),
                                    q.y(), q.z(), q.w());
                    });
}

Status WriteKittiTrajectory(const std::string& path, const Trajectory& trajectory) {
  if (Status s = CheckStamps(path, trajectory, nullptr); !s.ok()) return s;
  return WriteLines(path, trajectory, nullptr, [&](char* b, std::size_t n, std::size_t i) {
    const Eigen::Matrix<double, 3, 4> T = trajectory.poses[i].matrix3x4();
    std::snprintf(b, n, "%.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e\n", T(0, 0),
                  T(0, 1), T(0, 2), T(0, 3), T(1, 0), T(1, 1), T(1, 2), T(1, 3), T(2, 0), T(2, 1), T(2, 2),
                  T(2, 3));
  });
}

Status WriteEurocTrajectory(const std::string& path, const Trajectory& trajectory) {
  if (Status s = CheckStamps(path, trajectory, "EuRoC"); !s.ok()) return s;
  const char* header =
      "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n";
  return WriteLines(path, trajectory, header, [&](char* b, std::size_t n, std::size_t i) {
    const Eigen::Vector3d& t = trajectory.poses[i].translation();
    const Eigen::Quaterniond q = trajectory.poses[i].so3().quaternion();
    std::snprintf(b, n, "%lld,%.9f,%.9f,%.9f,%.12f,%.12f,%.12f,%.12f\n",
                  static_cast<long long>(trajectory.stamps[i]), t.x(), t.y(), t.z(), q.w(), q.x(), q.y(),
                  q.z());
  });
}

}  // namespace uf
