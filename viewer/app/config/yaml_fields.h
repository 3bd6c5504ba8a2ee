// Parsing a YAML section of settings onto an option struct, shared by the configuration readers
// (estimator_config.cpp, splat_config.cpp): a setter per key that parses its node into the field or returns
// the error text, ParseMap that applies them (unknown keys are errors listing the known ones) and the
// "FILE: section.key (line N): what" error. Includes yaml-cpp: for .cpp files only.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <optional>
#include <string>

#include "odometry/types/status.h"

namespace uf::app::yaml {

using Setter = std::function<std::optional<std::string>(const YAML::Node&)>;
// Nested sections by key: parse the sub-map at the given path.
using Nested = std::map<std::string, std::function<Status(const std::string&, const YAML::Node&)>>;

// The node's text, or "<not a scalar>".
std::string Scalar(const YAML::Node& node);

Setter Number(double& field);  // a finite number
Setter Boolean(bool& field);   // true / false

// A whole number of the field's type (int, std::size_t, std::uint64_t, ...).
template <typename Int>
Setter Whole(Int& field) {
  return [&field](const YAML::Node& node) -> std::optional<std::string> {
    Int value = 0;
    if (!node.IsScalar() || !YAML::convert<Int>::decode(node, value))
      return "expected a whole number, got '" + Scalar(node) + "'";
    field = value;
    return std::nullopt;
  };
}

// "FILE: PATH (line N): what"; PATH is the dotted key, e.g. "lo.map.voxel_m".
Status KeyError(const std::string& file, const std::string& path, const YAML::Node& node,
                const std::string& what);

// Applies `setters` (and `nested`) to the map `node` found at `path`.
Status ParseMap(const std::string& file, const std::string& path, const YAML::Node& node,
                const std::map<std::string, Setter>& setters, const Nested& nested = {});

// The shortest text that reads back to the same double (for files that must read back exactly).
std::string FormatNumber(double value);

}  // namespace uf::app::yaml
