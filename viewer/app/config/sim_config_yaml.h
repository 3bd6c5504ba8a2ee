// Typed reading of YAML nodes for sim_config.cpp, with errors that name the file, the key path, the line
// and the bad text ("FILE: sim.lidar.rate_hz (line 12): expected a number, got 'fast'"). Internal to
// uf_app_config; yaml-cpp stays out of the public headers.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "odometry/sim/time_window.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::app::yaml {

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
  const std::string& path() const { return path_; }

 private:
  std::string file_, path_;
};

// The scalar's text; a list or map on one line ("[3, 1]"); "" for nothing.
std::string Text(const YAML::Node& node);

// Scalars. Numbers are read with std::from_chars (the exact nearest double, so the shortest round-trip
// text of EmitSimConfig reads back bit for bit); booleans are true | false.
Status Read(const KeyPath& at, const YAML::Node& node, double& value);
Status Read(const KeyPath& at, const YAML::Node& node, int& value);
Status Read(const KeyPath& at, const YAML::Node& node, std::uint64_t& value);
Status Read(const KeyPath& at, const YAML::Node& node, bool& value);
Status Read(const KeyPath& at, const YAML::Node& node, std::string& value);
Status Read(const KeyPath& at, const YAML::Node& node, Eigen::Vector3d& value);  // [x, y, z]
// Decimal seconds parsed exactly to the nanosecond (uf::ParseSeconds).
Status ReadSeconds(const KeyPath& at, const YAML::Node& node, Stamp& value);
// [begin_s, end_s] relative to `start` -> absolute stamps; end <= begin is an error.
Status ReadWindow(const KeyPath& at, const YAML::Node& node, Stamp start, sim::TimeWindow& window);
// {translation_m, rotation_rpy_deg} or {matrix} (see sim_config.h) over the current value of T.
Status ReadExtrinsic(const KeyPath& at, const YAML::Node& node, SE3& T);

// A map of known keys, each with the function that reads its value. Null (an empty section) is fine.
using FieldReader = std::function<Status(const KeyPath& at, const YAML::Node& value)>;
struct Field {
  std::string key;
  FieldReader read;
};
Status ReadMap(const KeyPath& at, const YAML::Node& node, const std::vector<Field>& fields);

// A field read by the Read overload of its type.
template <typename T>
Field Value(std::string key, T& target) {
  return {std::move(key),
          [&target](const KeyPath& at, const YAML::Node& node) { return Read(at, node, target); }};
}

// A list field: `read_item` reads element i (at its own path) and appends it; the list replaces `target`.
template <typename T>
Field List(std::string key, std::vector<T>& target,
           std::function<Status(const KeyPath&, const YAML::Node&, T&)> read_item) {
  return {std::move(key), [&target, read_item](const KeyPath& at, const YAML::Node& node) -> Status {
            if (!node.IsSequence()) return at.Error(node, "expected a list, got '" + Text(node) + "'");
            std::vector<T> items(node.size());
            for (std::size_t i = 0; i < node.size(); ++i) {
              if (Status s = read_item(at[i], node[i], items[i]); !s.ok()) return s;
            }
            target = std::move(items);
            return {};
          }};
}

}  // namespace uf::app::yaml
