#include "viewer/app/config/yaml_fields.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace uf::app::yaml {

std::string Scalar(const YAML::Node& node) {
  return node.IsScalar() ? node.Scalar() : std::string("<not a scalar>");
}

Setter Number(double& field) {
  return [&field](const YAML::Node& node) -> std::optional<std::string> {
    double value = 0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value))
      return "expected a number, got '" + Scalar(node) + "'";
    field = value;
    return std::nullopt;
  };
}

Setter Boolean(bool& field) {
  return [&field](const YAML::Node& node) -> std::optional<std::string> {
    bool value = false;
    if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
      return "expected true or false, got '" + Scalar(node) + "'";
    field = value;
    return std::nullopt;
  };
}

Status KeyError(const std::string& file, const std::string& path, const YAML::Node& node,
                const std::string& what) {
  std::string where = file + ": " + path;
  if (node.Mark().line >= 0) where += " (line " + std::to_string(node.Mark().line + 1) + ")";
  return Status::Error(where + ": " + what);
}

Status ParseMap(const std::string& file, const std::string& path, const YAML::Node& node,
                const std::map<std::string, Setter>& setters, const Nested& nested) {
  if (!node.IsMap()) return KeyError(file, path, node, "expected a map of settings");
  std::string expected;
  for (const auto& [key, setter] : setters) expected += (expected.empty() ? "" : ", ") + key;
  for (const auto& [key, parse] : nested) expected += ", " + key;
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    if (const auto sub = nested.find(key); sub != nested.end()) {
      if (Status s = sub->second(path + "." + key, kv.second); !s.ok()) return s;
      continue;
    }
    const auto setter = setters.find(key);
    if (setter == setters.end())
      return KeyError(file, path + "." + key, kv.first, "unknown key (expected " + expected + ")");
    if (auto error = setter->second(kv.second)) return KeyError(file, path + "." + key, kv.second, *error);
  }
  return {};
}

std::string FormatNumber(double value) {
  char text[32];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

}  // namespace uf::app::yaml
