#include "odometry/io/folders/folder_common.h"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

namespace uf {

Expected<SE3> TransformFromRowMajor(const std::vector<double>& values, const std::string& where) {
  if (values.size() != 16)
    return Status::Error(where + ": a 4x4 transform needs 16 numbers, found " +
                         std::to_string(values.size()));
  Eigen::Matrix4d T;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T(r, c) = values[4 * r + c];
  if (!T.allFinite()) return Status::Error(where + ": transform has a non-finite entry");
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    return Status::Error(where + ": the last row of the transform must be 0 0 0 1");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (error > 1e-6 || R.determinant() < 0) {
    std::ostringstream text;
    text << where << ": the rotation part is not a rotation (max |R^T R - I| = " << error
         << ", det = " << R.determinant() << ")";
    return Status::Error(text.str());
  }
  return SE3::FromMatrix(T);
}

std::vector<double> RowMajor(const SE3& transform) {
  const Eigen::Matrix4d T = transform.matrix();
  std::vector<double> values;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) values.push_back(T(r, c));
  return values;
}

std::string RelativeName(const std::filesystem::path& file, const std::filesystem::path& root) {
  const std::filesystem::path relative = file.lexically_normal().lexically_relative(root.lexically_normal());
  if (relative.empty() || relative.string().starts_with("..")) return file.generic_string();
  return relative.generic_string();
}

std::string FolderName(const std::filesystem::path& folder) {
  std::filesystem::path normal = folder.lexically_normal();
  if (!normal.has_filename()) normal = normal.parent_path();
  if (normal.filename() == "." || normal.empty())
    normal = std::filesystem::absolute(folder).lexically_normal();
  if (!normal.has_filename()) normal = normal.parent_path();
  return normal.filename().string();
}

bool IsInsideFolder(const std::filesystem::path& relative) {
  if (relative.empty() || relative.is_absolute() || relative.has_root_name()) return false;
  for (const auto& part : relative.lexically_normal())
    if (part == "..") return false;
  return true;
}

}  // namespace uf
