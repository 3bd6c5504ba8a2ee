#include "odometry/io/folders/yaml_keys.h"

namespace uf {

Status CheckKeys(const YAML::Node& map, const std::set<std::string>& known, const std::string& where) {
  for (const auto& entry : map) {
    const std::string key = entry.first.as<std::string>();
    if (known.contains(key)) continue;
    std::string expected;
    for (const std::string& name : known) expected += (expected.empty() ? "" : ", ") + name;
    return Status::Error(where + ": unknown key '" + key + "' (expected " + expected + ")");
  }
  return {};
}

}  // namespace uf
