// Small helpers the folder readers and the dataset writer share. Internal to uf_io.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf {

// A 4x4 homogeneous transform from 16 row-major numbers. The last row must be 0 0 0 1 and the rotation
// orthonormal with determinant +1 (to 1e-6); errors start with `where`.
Expected<SE3> TransformFromRowMajor(const std::vector<double>& values, const std::string& where);
std::vector<double> RowMajor(const SE3& transform);  // the 16 numbers, inverse of the above

// `file` relative to `root` in generic form ("mav0/imu0/data.csv"), or `file` itself when not below it.
std::string RelativeName(const std::filesystem::path& file, const std::filesystem::path& root);

// The folder's own name, also for paths written with a trailing separator ("seq/00/" -> "00").
std::string FolderName(const std::filesystem::path& folder);

// Whether a path read from a dataset file stays inside the dataset folder (relative, no "..").
bool IsInsideFolder(const std::filesystem::path& relative);

}  // namespace uf
