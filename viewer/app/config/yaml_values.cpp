#include "viewer/app/config/yaml_values.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace uf::app::config {
namespace {

Status ReadFinite(const KeyPath& at, const YAML::Node& node, std::optional<double> parsed, double& value) {
  if (!parsed || !std::isfinite(*parsed))
    return at.Error(node, "expected a number, got '" + Text(node) + "'");
  value = *parsed;
  return {};
}

template <typename Vector>
std::string FormatVector(const Vector& v) {
  return Cat({"[", FormatNumber(v.x()), ", ", FormatNumber(v.y()), ", ", FormatNumber(v.z()), "]"});
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
  return ReadFinite(at, node, node.IsScalar() ? FromChars<double>(node.Scalar()) : std::nullopt, value);
}

Status Read(const KeyPath& at, const YAML::Node& node, float& value) {
  const std::optional<float> parsed = node.IsScalar() ? FromChars<float>(node.Scalar()) : std::nullopt;
  if (!parsed || !std::isfinite(*parsed))
    return at.Error(node, "expected a number, got '" + Text(node) + "'");
  value = *parsed;
  return {};
}

Status Read(const KeyPath& at, const YAML::Node& node, bool& value) {
  const std::string text = Text(node);
  const bool is_true = text == "true" || text == "True" || text == "TRUE";
  const bool is_false = text == "false" || text == "False" || text == "FALSE";
  if (!node.IsScalar() || (!is_true && !is_false))
    return at.Error(node, "expected true or false, got '" + text + "'");
  value = is_true;
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

Status ReadNumbers(const KeyPath& at, const YAML::Node& node, std::size_t n, double* values) {
  if (!node.IsSequence() || node.size() != n) {
    return at.Error(node, "expected a list of " + std::to_string(n) + " numbers, got '" + Text(node) + "'");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (Status s = Read(at[i], node[i], values[i]); !s.ok()) return s;
  }
  return {};
}

Status Read(const KeyPath& at, const YAML::Node& node, Eigen::Vector3d& value) {
  Eigen::Vector3d read;
  if (Status s = ReadNumbers(at, node, 3, read.data()); !s.ok()) return s;
  value = read;
  return {};
}

Status Read(const KeyPath& at, const YAML::Node& node, Eigen::Vector3f& value) {
  if (!node.IsSequence() || node.size() != 3)
    return at.Error(node, "expected a list of 3 numbers, got '" + Text(node) + "'");
  Eigen::Vector3f read;
  for (int i = 0; i < 3; ++i) {
    if (Status s = Read(at[i], node[i], read[i]); !s.ok()) return s;
  }
  value = read;
  return {};
}

Status ReadSeconds(const KeyPath& at, const YAML::Node& node, Stamp& value) {
  std::optional<Stamp> parsed = node.IsScalar() ? ParseSeconds(node.Scalar()) : std::nullopt;
  if (!parsed) return at.Error(node, "expected a number of seconds, got '" + Text(node) + "'");
  value = *parsed;
  return {};
}

std::string Cat(std::initializer_list<std::string_view> pieces) {
  std::string text;
  for (std::string_view piece : pieces) text += piece;
  return text;
}

std::string FormatNumber(double value) {
  char text[32];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::string Format(double value) { return FormatNumber(value); }

std::string Format(float value) { return FormatNumber(value); }

std::string Format(bool value) { return value ? "true" : "false"; }

std::string Format(const std::string& value) {
  std::string quoted = "\"";
  for (unsigned char c : value) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\x%02x", c);
      quoted += escape;
    } else {
      quoted += static_cast<char>(c);
    }
  }
  return quoted + "\"";
}

std::string Format(const Eigen::Vector3d& value) { return FormatVector(value); }

std::string Format(const Eigen::Vector3f& value) { return FormatVector(value.cast<double>()); }

std::string FormatExactSeconds(Stamp t) {
  std::string text = FormatSeconds(t);
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text;
}

}  // namespace uf::app::config
