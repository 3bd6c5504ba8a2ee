#include "viewer/app/config/sim_config_yaml.h"

#include <Eigen/LU>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>

namespace uf::app::yaml {
namespace {

// Reads the whole of `text` as a T with std::from_chars (a leading '+' allowed), or nullopt.
template <typename T>
std::optional<T> FromChars(std::string text) {
  if (!text.empty() && text.front() == '+') text.erase(0, 1);
  T value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end) return std::nullopt;
  return value;
}

template <typename T>
Status ReadNumber(const KeyPath& at, const YAML::Node& node, T& value, const char* what) {
  std::optional<T> parsed = node.IsScalar() ? FromChars<T>(node.Scalar()) : std::nullopt;
  if (!parsed) return at.Error(node, std::string("expected ") + what + ", got '" + Text(node) + "'");
  value = *parsed;
  return {};
}

// Exactly n numbers in a list.
Status ReadNumbers(const KeyPath& at, const YAML::Node& node, std::size_t n, double* values) {
  if (!node.IsSequence() || node.size() != n) {
    return at.Error(node, "expected a list of " + std::to_string(n) + " numbers, got '" + Text(node) + "'");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (Status s = Read(at[i], node[i], values[i]); !s.ok()) return s;
  }
  return {};
}

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

}  // namespace

Status KeyPath::Error(const YAML::Node& node, const std::string& what) const {
  std::string where = file_ + ": " + path_;
  if (node.IsDefined() && node.Mark().line >= 0)
    where += " (line " + std::to_string(node.Mark().line + 1) + ")";
  return Status::Error(where + ": " + what);
}

std::string Text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  if (!node.IsSequence() && !node.IsMap()) return "";
  YAML::Emitter flow;  // lists and maps on one line: "[3, 1]", "{gain: 2}"
  flow << YAML::Flow << node;
  return flow.c_str();
}

Status Read(const KeyPath& at, const YAML::Node& node, double& value) {
  return ReadNumber(at, node, value, "a number");
}

Status Read(const KeyPath& at, const YAML::Node& node, int& value) {
  return ReadNumber(at, node, value, "an integer");
}

Status Read(const KeyPath& at, const YAML::Node& node, std::uint64_t& value) {
  return ReadNumber(at, node, value, "an integer in [0, 2^64)");
}

Status Read(const KeyPath& at, const YAML::Node& node, bool& value) {
  const std::string text = Text(node);
  if (!node.IsScalar() || (text != "true" && text != "false"))
    return at.Error(node, "expected true or false, got '" + text + "'");
  value = text == "true";
  return {};
}

Status Read(const KeyPath& at, const YAML::Node& node, std::string& value) {
  if (node.IsNull()) {  // `file:` with nothing after it: the empty string
    value.clear();
    return {};
  }
  if (!node.IsScalar()) return at.Error(node, "expected a text, got '" + Text(node) + "'");
  value = node.Scalar();
  return {};
}

Status Read(const KeyPath& at, const YAML::Node& node, Eigen::Vector3d& value) {
  Eigen::Vector3d read;
  if (Status s = ReadNumbers(at, node, 3, read.data()); !s.ok()) return s;
  value = read;
  return {};
}

Status ReadSeconds(const KeyPath& at, const YAML::Node& node, Stamp& value) {
  std::optional<Stamp> parsed = node.IsScalar() ? ParseSeconds(node.Scalar()) : std::nullopt;
  if (!parsed) return at.Error(node, "expected a number of seconds, got '" + Text(node) + "'");
  value = *parsed;
  return {};
}

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

Status ReadExtrinsic(const KeyPath& at, const YAML::Node& node, SE3& T) {
  if (!node.IsMap()) return at.Error(node, "expected a map {translation_m, rotation_rpy_deg} or {matrix}");
  if (node["matrix"]) {
    if (node.size() != 1) {
      return at.Error(node, "give either matrix or translation_m and rotation_rpy_deg, not both");
    }
    Eigen::Matrix<double, 4, 4, Eigen::RowMajor> M;
    if (Status s = ReadNumbers(at / "matrix", node["matrix"], 16, M.data()); !s.ok()) return s;
    // A rigid transform: bottom row (0, 0, 0, 1) and a rotation (R^T R = I, det R = +1) up to rounding.
    const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
    const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
    if (M.row(3) != Eigen::RowVector4d(0, 0, 0, 1) || !(orthogonality < 1e-6) || !(R.determinant() > 0)) {
      return (at / "matrix")
          .Error(node["matrix"], "expected a rigid transform [R t; 0 0 0 1] with R a rotation, got '" +
                                     Text(node["matrix"]) + "'");
    }
    T = SE3::FromMatrix(M);
    return {};
  }
  Eigen::Vector3d translation = T.translation();
  SO3 rotation = T.so3();
  Status status =
      ReadMap(at, node,
              {Value("translation_m", translation),
               {"rotation_rpy_deg", [&rotation](const KeyPath& key, const YAML::Node& value) -> Status {
                  Eigen::Vector3d rpy;
                  if (Status s = Read(key, value, rpy); !s.ok()) return s;
                  rotation = SO3(RotationFromRollPitchYaw(rpy));
                  return {};
                }}});
  if (!status.ok()) return status;
  T = SE3(rotation, translation);
  return {};
}

Status ReadMap(const KeyPath& at, const YAML::Node& node, const std::vector<Field>& fields) {
  if (node.IsNull()) return {};
  if (!node.IsMap()) return at.Error(node, "expected a map of settings, got '" + Text(node) + "'");
  for (const auto& kv : node) {
    const std::string key = Text(kv.first);
    const Field* field = nullptr;
    for (const Field& candidate : fields) {
      if (candidate.key == key) field = &candidate;
    }
    if (field == nullptr || !kv.first.IsScalar()) {
      std::string known;
      for (const Field& candidate : fields) known += (known.empty() ? "" : ", ") + candidate.key;
      return (at / key).Error(kv.first, "unknown key (expected " + known + ")");
    }
    if (Status s = field->read(at / key, kv.second); !s.ok()) return s;
  }
  return {};
}

}  // namespace uf::app::yaml
