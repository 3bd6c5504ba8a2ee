// Where `ultrafusion run` writes: the folder given with --out, or a new versioned folder
// runs/<UTC time YYYYmmdd-HHMMSS>/ (with -2, -3, ... appended when that name is taken) and a runs/latest
// symbolic link to it, replaced atomically (a link under a temporary name renamed over the old one), so a
// reader never finds runs/latest missing or half-made.
#pragma once

#include <chrono>
#include <filesystem>

#include "odometry/types/status.h"

namespace uf::pipeline {

// "20261121-220314": the UTC calendar time of `time`, to the second.
std::string RunFolderName(std::chrono::system_clock::time_point time);

// Creates runs_root (if needed) and a new, empty folder in it named after `time`; returns its path.
// Errors name the folder.
Expected<std::filesystem::path> CreateVersionedRunFolder(const std::filesystem::path& runs_root,
                                                         std::chrono::system_clock::time_point time);

// Points runs_root/latest at `folder` (a relative link: the folder's name), replacing any previous link.
Status UpdateLatestLink(const std::filesystem::path& runs_root, const std::filesystem::path& folder);

}  // namespace uf::pipeline
