// Unknown-key check for YAML maps in dataset and calibration files. Internal to uf_io.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

#include "odometry/types/status.h"

namespace uf {

// Error "WHERE: unknown key 'KEY' (expected a, b, c)" for the first key of `map` not in `known`.
Status CheckKeys(const YAML::Node& map, const std::set<std::string>& known, const std::string& where);

}  // namespace uf
