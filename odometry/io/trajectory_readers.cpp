// Readers of TUM, KITTI and EuRoC trajectory files, and of KITTI-style times files.
#include <cmath>

#include "odometry/io/text_table.h"
#include "odometry/io/trajectory_file.h"

namespace uf {
namespace {

constexpr double kUnitTolerance = 1e-2;  // quaternion norm / rotation orthonormality accepted from files

// Reads a quaternion from four columns in the given order of (w, x, y, z) positions.
Expected<Eigen::Quaterniond> ReadQuaternion(const TextTableReader& in, std::size_t w, std::size_t x,
                                            std::size_t y, std::size_t z) {
  double q[4];
  const std::size_t columns[4] = {w, x, y, z};
  const char* names[4] = {"qw", "qx", "qy", "qz"};
  for (int k = 0; k < 4; ++k) {
    auto v = in.Number(columns[k], names[k]);
    if (!v) return v.status();
    q[k] = *v;
  }
  Eigen::Quaterniond quaternion(q[0], q[1], q[2], q[3]);
  const double norm = quaternion.norm();
  if (std::abs(norm - 1.0) > kUnitTolerance)
    return in.Error("quaternion norm is " + std::to_string(norm) + ", not 1 (wrong column order or units?)");
  return quaternion;
}

Expected<Eigen::Vector3d> ReadVector(const TextTableReader& in, std::size_t first) {
  const char* names[3] = {"x", "y", "z"};
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    auto value = in.Number(first + k, names[k]);
    if (!value) return value.status();
    v[k] = *value;
  }
  return v;
}

Status EmptyCheck(const TextTableReader& in, const Trajectory& trajectory) {
  if (trajectory.empty()) return Status::Error(in.path() + ": no poses in file");
  return {};
}

// Where a stamped-pose format keeps its fields: the stamp in column 0, then x y z, then a quaternion.
struct StampedPoseLayout {
  TrajectoryFormat format;
  const char* description;     // for the column-count error
  bool extra_columns_allowed;  // EuRoC ground truth carries velocities and biases after the pose
  bool stamp_in_nanoseconds;   // else seconds
  std::size_t qw, qx, qy, qz;  // quaternion columns
};

constexpr StampedPoseLayout kTumLayout{
    TrajectoryFormat::kTum, "TUM: t x y z qx qy qz qw", false, false, 7, 4, 5, 6};
constexpr StampedPoseLayout kEurocLayout{
    TrajectoryFormat::kEuroc, "EuRoC: t[ns], x, y, z, qw, qx, qy, qz", true, true, 4, 5, 6, 7};

Expected<Trajectory> ReadStampedPoses(const std::string& path, const StampedPoseLayout& layout,
                                      const TrajectoryReadOptions& options, TrajectoryReadReport* report) {
  auto opened = TextTableReader::Open(path);
  if (!opened) return opened.status();
  TextTableReader& in = *opened;
  Trajectory trajectory;
  StampOrderCheck order(options.skip_duplicate_stamps);
  while (in.Next()) {
    if (Status s = in.ExpectColumns(8, layout.description, layout.extra_columns_allowed); !s.ok()) return s;
    auto stamp =
        layout.stamp_in_nanoseconds ? in.Nanoseconds(0, "timestamp [ns]") : in.Seconds(0, "timestamp");
    if (!stamp) return stamp.status();
    auto keep = order.Add(in, *stamp);
    if (!keep) return keep.status();
    if (!*keep) continue;
    auto t = ReadVector(in, 1);
    if (!t) return t.status();
    auto q = ReadQuaternion(in, layout.qw, layout.qx, layout.qy, layout.qz);
    if (!q) return q.status();
    trajectory.stamps.push_back(*stamp);
    trajectory.poses.emplace_back(SO3(*q), *t);
  }
  if (Status s = EmptyCheck(in, trajectory); !s.ok()) return s;
  if (report) {
    report->format = layout.format;
    report->skipped_duplicates = order.skipped();
    report->first_skipped_line = order.first_skipped_line();
  }
  return trajectory;
}

}  // namespace

Expected<Trajectory> ReadTumTrajectory(const std::string& path, const TrajectoryReadOptions& options,
                                       TrajectoryReadReport* report) {
  return ReadStampedPoses(path, kTumLayout, options, report);
}

Expected<Trajectory> ReadEurocTrajectory(const std::string& path, const TrajectoryReadOptions& options,
                                         TrajectoryReadReport* report) {
  return ReadStampedPoses(path, kEurocLayout, options, report);
}

Expected<Trajectory> ReadKittiTrajectory(const std::string& path) {
  auto opened = TextTableReader::Open(path);
  if (!opened) return opened.status();
  TextTableReader& in = *opened;
  Trajectory trajectory;
  while (in.Next()) {
    if (Status s = in.ExpectColumns(12, "KITTI: r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz"); !s.ok())
      return s;
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    for (int k = 0; k < 12; ++k) {
      auto v = in.Number(k, k % 4 == 3 ? "translation" : "rotation");
      if (!v) return v.status();
      T(k / 4, k % 4) = *v;
    }
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    const double deviation = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (deviation > kUnitTolerance || R.determinant() < 0)
      return in.Error("the 3x3 block is not a rotation (|R^T R - I| = " + std::to_string(deviation) +
                      ", det = " + std::to_string(R.determinant()) + ")");
    trajectory.poses.push_back(SE3::FromMatrix(T));  // kept exactly as written, as evo keeps it
  }
  if (Status s = EmptyCheck(in, trajectory); !s.ok()) return s;
  return trajectory;
}

namespace {

// One time in seconds per line (a '#' comment may follow it); strictly increasing when `increasing`.
Expected<std::vector<Stamp>> ReadStampLines(const std::string& path, bool increasing) {
  auto opened = TextTableReader::Open(path);
  if (!opened) return opened.status();
  TextTableReader& in = *opened;
  std::vector<Stamp> stamps;
  StampOrderCheck order;
  while (in.Next()) {
    const bool commented = in.columns() > 1 && in.field(1).front() == '#';
    if (!commented)
      if (Status s = in.ExpectColumns(1, "one time in seconds per line"); !s.ok()) return s;
    auto stamp = in.Seconds(0, "time");
    if (!stamp) return stamp.status();
    if (increasing)
      if (auto keep = order.Add(in, *stamp); !keep) return keep.status();
    stamps.push_back(*stamp);
  }
  if (Status s = in.read_status(); !s.ok()) return s;
  if (stamps.empty()) return Status::Error(path + ": no times in file");
  return stamps;
}

}  // namespace

Expected<std::vector<Stamp>> ReadTimesFile(const std::string& path) { return ReadStampLines(path, true); }

Expected<std::vector<Stamp>> ReadStampsFile(const std::string& path) { return ReadStampLines(path, false); }

Status AttachStamps(Trajectory& trajectory, std::vector<Stamp> stamps, const std::string& times_path) {
  if (stamps.size() != trajectory.size())
    return Status::Error(times_path + ": " + std::to_string(stamps.size()) + " times for " +
                         std::to_string(trajectory.size()) + " poses; the counts must agree");
  trajectory.stamps = std::move(stamps);
  return {};
}

}  // namespace uf
