#include "odometry/estimator/visual/triangulation.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
constexpr double kMinHomogeneousScale = 1e-12;  // |X_w| below this relative to |X|: a point at infinity

}  // namespace

Expected<Triangulation> Triangulate(std::span<const SE3> T_world_cam,
                                    std::span<const Eigen::Vector2d> normalized, double min_parallax_deg,
                                    double min_depth_m) {
  const std::size_t n = T_world_cam.size();
  if (n < 2 || normalized.size() != n)
    return Status::Error(PrintfText(
        "triangulation: %.0f poses and %.0f observations, at least 2 of each wanted", n, normalized.size()));
  Eigen::MatrixXd A(2 * n, 4);
  for (std::size_t k = 0; k < n; ++k) {
    const SE3 T_cam_world = T_world_cam[k].inverse();
    Eigen::Matrix<double, 3, 4> P;
    P << T_cam_world.so3().matrix(), T_cam_world.translation();
    A.row(2 * k) = normalized[k].x() * P.row(2) - P.row(0);
    A.row(2 * k + 1) = normalized[k].y() * P.row(2) - P.row(1);
  }
  const Eigen::Vector4d X = Eigen::JacobiSVD<Eigen::MatrixXd>(A, Eigen::ComputeFullV).matrixV().col(3);
  if (std::abs(X(3)) < kMinHomogeneousScale * X.norm())
    return Status::Error("triangulation: the rays meet at infinity");
  Triangulation t;
  t.point_world = X.head<3>() / X(3);
  t.min_depth_m = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p_cam = T_world_cam[k].inverse() * t.point_world;
    t.min_depth_m = std::min(t.min_depth_m, p_cam.z());
    if (p_cam.z() > 0)
      t.max_reprojection = std::max(t.max_reprojection, (p_cam.head<2>() / p_cam.z() - normalized[k]).norm());
    for (std::size_t l = k + 1; l < n; ++l) {
      const Eigen::Vector3d a = (t.point_world - T_world_cam[k].translation()).normalized();
      const Eigen::Vector3d b = (t.point_world - T_world_cam[l].translation()).normalized();
      t.parallax_deg = std::max(t.parallax_deg, std::acos(std::clamp(a.dot(b), -1.0, 1.0)) / kDegree);
    }
  }
  if (t.min_depth_m < min_depth_m)
    return Status::Error(PrintfText("triangulation: depth %.3f m in one camera, at least %.3f m wanted",
                                    t.min_depth_m, min_depth_m));
  if (t.parallax_deg < min_parallax_deg)
    return Status::Error(PrintfText("triangulation: parallax %.3f deg, at least %.3f deg wanted",
                                    t.parallax_deg, min_parallax_deg));
  return t;
}

double InverseDepth(const SE3& T_world_anchor_cam, const Eigen::Vector3d& point_world) {
  return 1.0 / (T_world_anchor_cam.inverse() * point_world).z();
}

}  // namespace uf::estimator
