#include "odometry/estimator/schedule/camera_motion_check.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

namespace uf::estimator {

TrackMotionCheck CheckTrackMotion(const Eigen::Vector2d& x_j, const Eigen::Vector2d& x_k, const SE3& T_k_j,
                                  double focal_px, double tolerance_px) {
  const Eigen::Matrix3d R = T_k_j.so3().matrix();
  const Eigen::Vector3d t = T_k_j.translation();
  const Eigen::Vector3d a = R * x_j.homogeneous(), b = x_k.homogeneous();
  TrackMotionCheck out;
  out.error_px = a.z() > 0 ? (a.hnormalized() - x_k).norm() * focal_px : INFINITY;
  if (out.error_px <= tolerance_px) {
    out.agrees = true;
    return out;
  }
  // Sampson distance of the epipolar constraint b^T E x_j = 0, E = [t]x R (normalized units).
  const Eigen::Vector3d x1 = x_j.homogeneous();
  const Eigen::Matrix3d E = Hat(t) * R;
  const Eigen::Vector3d Ex1 = E * x1, Etb = E.transpose() * b;
  const double denominator = Ex1.head<2>().squaredNorm() + Etb.head<2>().squaredNorm();
  if (!(denominator > 1e-18)) return out;  // no translation: the rotation alone had to explain it
  const double sampson_px = std::abs(b.dot(Ex1)) / std::sqrt(denominator) * focal_px;
  // Depths: [b, -a] (z_k, z_j)^T = t in least squares.
  Eigen::Matrix<double, 3, 2> A;
  A << b, -a;
  const Eigen::Vector2d z = A.colPivHouseholderQr().solve(t);
  if (!(z.x() > 0 && z.y() > 0)) return out;
  out.error_px = std::min(out.error_px, sampson_px);
  out.agrees = sampson_px <= tolerance_px;
  return out;
}

CameraCheck ScoreCameraMotion(Stamp stamp, const std::vector<CheckedTrack>& tracks, int width, int height,
                              int grid_cells, const CameraScoreConfig& config) {
  CameraCheck check;
  check.stamp = stamp;
  check.tracks_checked = static_cast<int>(tracks.size());
  std::vector<double> errors;
  std::set<int> cells;
  for (const CheckedTrack& track : tracks) {
    // A non-finite error (a diverged pose) counts as the worst: NaN would break the median's ordering.
    errors.push_back(std::isnan(track.check.error_px) ? INFINITY : track.check.error_px);
    if (!track.check.agrees) continue;
    ++check.tracks_agreeing;
    const int cx = std::clamp(static_cast<int>(track.pixel.x() * grid_cells / width), 0, grid_cells - 1);
    const int cy = std::clamp(static_cast<int>(track.pixel.y() * grid_cells / height), 0, grid_cells - 1);
    cells.insert(cy * grid_cells + cx);
  }
  check.grid_occupancy = static_cast<double>(cells.size()) / (grid_cells * grid_cells);
  if (!errors.empty()) {
    const auto middle = errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2);
    std::nth_element(errors.begin(), middle, errors.end());
    check.motion_error_px = *middle;
  }
  check.score =
      ScoreCameraFrame(check.tracks_agreeing, check.grid_occupancy, check.motion_error_px, config).score;
  return check;
}

}  // namespace uf::estimator
