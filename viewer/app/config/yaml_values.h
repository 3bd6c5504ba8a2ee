// Reading and writing single YAML values of the configuration file: the one helper set of the schema
// (schema.h) and its codecs. Reads name the file, the key path, the line and the bad text
// ("FILE: sim.lidar.rate_hz (line 12): expected a number, got 'fast'"); writes give the text that reads back
// to exactly the same value. Internal to uf_app_config: yaml-cpp stays out of the public headers.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <charconv>
#include <concepts>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::app::config {

// Where a node sits: the file and the dotted key path ("sim.camera.darkness[1]").
class KeyPath {
 public:
  KeyPath(std::string file, std::string path) : file_(std::move(file)), path_(std::move(path)) {}
  KeyPath operator/(const std::string& key) const { return KeyPath(file_, path_ + "." + key); }
  KeyPath operator[](std::size_t index) const {
    return KeyPath(file_, path_ + "[" + std::to_string(index) + "]");
  }
  // "FILE: PATH (line N): what", the line of `node` (1-based) when it has one.
  Status Error(const YAML::Node& node, const std::string& what) const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

 private:
  std::string file_, path_;
};

// The scalar's text; a list or map on one line ("[3, 1]"); "" for nothing.
std::string Text(const YAML::Node& node);

// The whole of `text` as a T by std::from_chars (a leading '+' allowed), or nothing: numbers are the exact
// nearest value, so the shortest round-trip text of FormatNumber reads back bit for bit.
template <typename T>
std::optional<T> FromChars(std::string text) {
  if (!text.empty() && text.front() == '+') text.erase(0, 1);
  T value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end) return std::nullopt;
  return value;
}

// Scalars and fixed-size lists. Numbers must be finite; booleans are true | false (True, TRUE, False, FALSE);
// a null node reads as the empty text.
Status Read(const KeyPath& at, const YAML::Node& node, double& value);
Status Read(const KeyPath& at, const YAML::Node& node, float& value);
Status Read(const KeyPath& at, const YAML::Node& node, bool& value);
Status Read(const KeyPath& at, const YAML::Node& node, std::string& value);
Status Read(const KeyPath& at, const YAML::Node& node, Eigen::Vector3d& value);  // [x, y, z]
Status Read(const KeyPath& at, const YAML::Node& node, Eigen::Vector3f& value);  // [x, y, z]

// Whole numbers of the field's type (int, std::size_t, std::uint64_t, ...), in its range.
template <typename Int>
requires(std::integral<Int> && !std::same_as<Int, bool>) Status
    Read(const KeyPath& at, const YAML::Node& node, Int& value) {
  const std::optional<Int> parsed = node.IsScalar() ? FromChars<Int>(node.Scalar()) : std::nullopt;
  if (!parsed) {
    return at.Error(node,
                    std::string(std::is_signed_v<Int> ? "expected an integer" : "expected an integer >= 0") +
                        ", got '" + Text(node) + "'");
  }
  value = *parsed;
  return {};
}

// Exactly n numbers in a list.
Status ReadNumbers(const KeyPath& at, const YAML::Node& node, std::size_t n, double* values);

// Decimal seconds parsed exactly to the nanosecond (uf::ParseSeconds).
Status ReadSeconds(const KeyPath& at, const YAML::Node& node, Stamp& value);

// The pieces one after the other (no "literal" + std::string chains: GCC 12 warns falsely on some).
std::string Cat(std::initializer_list<std::string_view> pieces);

// The texts that read back to the same value.
std::string FormatNumber(double value);  // the shortest "%g" text that reads back exactly
std::string Format(double value);
std::string Format(float value);  // the float's exact double value, shortest
std::string Format(bool value);
std::string Format(const std::string& value);  // double-quoted: any text reads back unchanged
std::string Format(const Eigen::Vector3d& value);
std::string Format(const Eigen::Vector3f& value);
template <typename Int>
requires(std::integral<Int> && !std::same_as<Int, bool>) std::string Format(Int value) {
  return std::to_string(value);
}
// Exact decimal seconds without trailing zeros: 1700000000.5, not 1700000000.500000000.
std::string FormatExactSeconds(Stamp t);

}  // namespace uf::app::config
