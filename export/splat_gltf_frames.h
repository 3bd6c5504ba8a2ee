// Internal to the KHR_gaussian_splatting reader and writer (splat_gltf.h): attribute names and the change
// of axes between our z-up world and glTF's y-up frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace uf::exporting::gltf_splat {

inline const std::string kRotation = "KHR_gaussian_splatting:ROTATION";
inline const std::string kScale = "KHR_gaussian_splatting:SCALE";
inline const std::string kOpacity = "KHR_gaussian_splatting:OPACITY";

// KHR_gaussian_splatting:SH_DEGREE_l_COEF_n: coefficient m = n - l of degree l (3DGS index k = l^2 + n).
inline std::string ShAttribute(int l, int n) {
  return "KHR_gaussian_splatting:SH_DEGREE_" + std::to_string(l) + "_COEF_" + std::to_string(n);
}

// R_gltf_ours: (x, y, z)_gltf = (x, z, -y)_ours, a rotation of -90 deg about x.
inline Eigen::Matrix3d GltfFromOurs() {
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  return R;
}

}  // namespace uf::exporting::gltf_splat
