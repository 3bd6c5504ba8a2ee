// The top-level sections of an ultrafusion configuration file. One file may hold several; each reader
// (dataset_config.h, sim_config.h, the calibration reader, estimator_config.h) reads its own section, skips
// the other known ones and rejects any other top-level key with the list below.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace uf::app {

inline constexpr std::array<std::string_view, 6> kConfigSections = {"dataset", "sim", "calibration",
                                                                    "lo",      "lio", "splat"};

inline bool IsKnownConfigSection(std::string_view name) {
  for (std::string_view known : kConfigSections) {
    if (known == name) return true;
  }
  return false;
}

// "dataset, sim, calibration, lo, lio, splat": for error messages.
inline std::string KnownConfigSectionsList() {
  std::string list;
  for (std::string_view known : kConfigSections) {
    if (!list.empty()) list += ", ";
    list += known;
  }
  return list;
}

}  // namespace uf::app
