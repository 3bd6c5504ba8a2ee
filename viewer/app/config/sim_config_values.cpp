#include "viewer/app/config/sim_config_values.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace uf::app::config {
namespace {

// (cos, sin) of an angle in degrees; exactly 0 and +-1 at multiples of 90 degrees, so that the usual mounts
// (a forward camera: roll -90, yaw -90) give exact rotation matrices.
std::pair<double, double> CosSinDegrees(double degrees) {
  const double quarters = degrees / 90.0;
  if (quarters == std::round(quarters) && std::abs(quarters) < 1e15) {
    constexpr double kCos[4] = {1, 0, -1, 0}, kSin[4] = {0, 1, 0, -1};
    const int k = static_cast<int>(((static_cast<long long>(quarters) % 4) + 4) % 4);
    return {kCos[k], kSin[k]};
  }
  const double radians = degrees * std::numbers::pi / 180.0;
  return {std::cos(radians), std::sin(radians)};
}

// R = Rz(yaw) Ry(pitch) Rx(roll), angles in degrees: roll about x first, then pitch about y, then yaw about
// z (all about the fixed body axes).
Eigen::Matrix3d RotationFromRollPitchYaw(const Eigen::Vector3d& rpy_deg) {
  const auto [cr, sr] = CosSinDegrees(rpy_deg.x());
  const auto [cp, sp] = CosSinDegrees(rpy_deg.y());
  const auto [cy, sy] = CosSinDegrees(rpy_deg.z());
  Eigen::Matrix3d Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return Rz * Ry * Rx;
}

Status ReadMatrix(const KeyPath& at, const YAML::Node& node, SE3& T) {
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> M;
  if (Status s = ReadNumbers(at, node, 16, M.data()); !s.ok()) return s;
  // A rigid transform: bottom row (0, 0, 0, 1) and a rotation (R^T R = I, det R = +1) up to rounding.
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (M.row(3) != Eigen::RowVector4d(0, 0, 0, 1) || !(orthogonality < 1e-6) || !(R.determinant() > 0)) {
    return at.Error(node,
                    "expected a rigid transform [R t; 0 0 0 1] with R a rotation, got '" + Text(node) + "'");
  }
  T = SE3::FromMatrix(M);
  return {};
}

Status ReadExtrinsic(const KeyPath& at, const YAML::Node& node, SE3& T) {
  if (!node.IsMap()) return at.Error(node, "expected a map {translation_m, rotation_rpy_deg} or {matrix}");
  if (node["matrix"]) {
    if (node.size() != 1) {
      return at.Error(node, "give either matrix or translation_m and rotation_rpy_deg, not both");
    }
    return ReadMatrix(at / "matrix", node["matrix"], T);
  }
  struct Parts {
    Eigen::Vector3d translation;
    SO3 rotation;
  } parts = {T.translation(), T.so3()};
  Schema<Parts> schema;
  schema.Key("translation_m", &Parts::translation, "", "");
  schema.Custom(
      "rotation_rpy_deg",
      [](const KeyPath& key, const YAML::Node& value, Parts& p) -> Status {
        Eigen::Vector3d rpy;
        if (Status s = Read(key, value, rpy); !s.ok()) return s;
        p.rotation = SO3(RotationFromRollPitchYaw(rpy));
        return {};
      },
      nullptr, "", "");
  if (Status s = ReadMap(schema, at, node, parts); !s.ok()) return s;
  T = SE3(parts.rotation, parts.translation);
  return {};
}

// The matrix exactly, row-major, two spaces between rows; the translation and roll-pitch-yaw in a comment
// (and as the documented value).
ValueText WriteExtrinsic(const SE3& T) {
  const Eigen::Matrix4d M = T.matrix();
  std::string matrix;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (r > 0 || c > 0) matrix += c == 0 ? ",  " : ", ";
      matrix += FormatNumber(M(r, c));
    }
  }
  // R = Rz(yaw) Ry(pitch) Rx(roll) has first column (cy cp, sy cp, -sp) and last row (-sp, cp sr, cp cr)
  // (c = cos, s = sin), so roll = atan2(R21, R22), pitch = -asin(R20), yaw = atan2(R10, R00), away from
  // pitch = +-90 deg.
  const Eigen::Matrix3d& R = T.rotation();
  const auto degrees = [](double radians) { return radians * 180.0 / std::numbers::pi + 0.0; };  // no -0
  const Eigen::Vector3d t = T.translation() + Eigen::Vector3d::Zero();
  const Eigen::Vector3d rpy(degrees(std::atan2(R(2, 1), R(2, 2))),
                            degrees(-std::asin(std::clamp(R(2, 0), -1.0, 1.0))),
                            degrees(std::atan2(R(1, 0), R(0, 0))));
  char comment[200];
  std::snprintf(comment, sizeof(comment),
                "translation_m [%.6g, %.6g, %.6g], rotation_rpy_deg [%.6g, %.6g, %.6g]", t.x(), t.y(), t.z(),
                rpy.x(), rpy.y(), rpy.z());
  char doc[200];
  std::snprintf(doc, sizeof(doc), "{translation_m: [%.6g, %.6g, %.6g], rotation_rpy_deg: [%.6g, %.6g, %.6g]}",
                t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z());
  ValueText value{"{matrix: [" + matrix + "]}"};
  value.comment = comment;
  value.doc = doc;
  return value;
}

}  // namespace

Status ReadWindow(const KeyPath& at, const YAML::Node& node, Stamp start, sim::TimeWindow& window) {
  if (!node.IsSequence() || node.size() != 2)
    return at.Error(node, "expected a window [begin_s, end_s], got '" + Text(node) + "'");
  Stamp begin = 0, end = 0;
  if (Status s = ReadSeconds(at[0], node[0], begin); !s.ok()) return s;
  if (Status s = ReadSeconds(at[1], node[1], end); !s.ok()) return s;
  if (end <= begin) {
    return at.Error(
        node, "the window must end after it begins, got [" + Text(node[0]) + ", " + Text(node[1]) + "]");
  }
  // Relative to the sequence start -> absolute; refuse what int64 nanoseconds cannot hold.
  if (__builtin_add_overflow(start, begin, &window.begin) || __builtin_add_overflow(start, end, &window.end))
    return at.Error(node, "the window is out of range of the time stamps");
  return {};
}

std::string FormatWindow(const sim::TimeWindow& window, Stamp start) {
  return "[" + FormatExactSeconds(window.begin - start) + ", " + FormatExactSeconds(window.end - start) + "]";
}

Status ReadWindows(const KeyPath& at, const YAML::Node& node, Stamp start,
                   std::vector<sim::TimeWindow>& windows) {
  if (!node.IsSequence()) return at.Error(node, "expected a list, got '" + Text(node) + "'");
  std::vector<sim::TimeWindow> read(node.size());
  for (std::size_t i = 0; i < node.size(); ++i)
    if (Status s = ReadWindow(at[i], node[i], start, read[i]); !s.ok()) return s;
  windows = std::move(read);
  return {};
}

std::string FormatWindows(const std::vector<sim::TimeWindow>& windows, Stamp start) {
  std::string list;
  for (const sim::TimeWindow& window : windows)
    list += (list.empty() ? "" : ", ") + FormatWindow(window, start);
  return "[" + list + "]";
}

Codec<SE3> ExtrinsicCodec() { return {ReadExtrinsic, WriteExtrinsic}; }

}  // namespace uf::app::config
