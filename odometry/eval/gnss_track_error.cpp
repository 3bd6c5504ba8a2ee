#include "odometry/eval/gnss_track_error.h"

#include <cmath>
#include <vector>

#include "odometry/eval/gnss_alignment.h"

namespace uf {

Expected<GnssTrackError> CompareWithGnssTrack(const Trajectory& trajectory, std::span<const GnssFix> fixes,
                                              const SE3& T_frame_antenna,
                                              const std::optional<GeodeticOrigin>& georeferenced_origin,
                                              bool gravity_aligned, double segment_m) {
  GnssTrackError result;
  result.segment_m = segment_m;
  GeodeticOrigin origin;
  SE3 T_enu_world;  // identity for a georeferenced trajectory
  if (georeferenced_origin) {
    origin = *georeferenced_origin;
  } else {
    GnssAlignmentOptions options;
    options.T_body_antenna = T_frame_antenna;
    options.gravity_aligned = gravity_aligned;
    options.max_rms_m = 1e9;  // a poor fit is the figure here, not a reason to give none
    Expected<GnssAlignment> fit = AlignToGnss(trajectory, fixes, options);
    if (!fit) return fit.status();
    origin = fit->origin;
    T_enu_world = fit->T_enu_world;
    result.aligned = true;
  }
  Expected<EnuFrame> frame = EnuFrame::Create(origin);
  if (!frame) return frame.status();
  std::vector<Eigen::Vector3d> antenna, enu;
  for (const GnssFix& fix : fixes) {
    if (fix.status == GnssFixStatus::kNoFix) continue;
    const Eigen::Vector3d geodetic(fix.latitude_deg, fix.longitude_deg, fix.altitude_m);
    const std::optional<SE3> pose = trajectory.PoseAt(fix.stamp);
    if (!pose || !geodetic.allFinite()) continue;
    antenna.push_back(T_enu_world * (*pose * T_frame_antenna.translation()));
    enu.push_back(frame->EnuFromGeodetic(geodetic));
  }
  result.fixes = static_cast<int>(antenna.size());
  if (antenna.empty()) return Status::Error("no GNSS fix with a position within the trajectory's time span");
  double horizontal = 0, vertical = 0;
  for (std::size_t i = 0; i < antenna.size(); ++i) {
    const Eigen::Vector3d e = antenna[i] - enu[i];
    result.horizontal_error_m.push_back(e.head<2>().norm());
    horizontal += e.head<2>().squaredNorm();
    vertical += e.z() * e.z();
  }
  const double n = static_cast<double>(antenna.size());
  result.horizontal_rmse_m = std::sqrt(horizontal / n);
  result.vertical_rmse_m = std::sqrt(vertical / n);
  // Track length along the fixes, and the segments: track[i] is the horizontal distance from the first fix.
  std::vector<double> track(enu.size(), 0.0);
  for (std::size_t i = 1; i < enu.size(); ++i)
    track[i] = track[i - 1] + (enu[i] - enu[i - 1]).head<2>().norm();
  result.track_length_m = track.back();
  double sum = 0;
  int segments = 0;
  std::size_t j = 0;
  for (std::size_t i = 0; i < enu.size(); ++i) {
    j = std::max(j, i + 1);
    while (j < enu.size() && track[j] - track[i] < segment_m) ++j;
    if (j >= enu.size()) break;
    const Eigen::Vector3d error = (antenna[j] - antenna[i]) - (enu[j] - enu[i]);
    sum += error.head<2>().norm() / (track[j] - track[i]);
    ++segments;
  }
  if (segments > 0) result.segment_error_percent = 100.0 * sum / segments;
  result.antenna_enu = std::move(antenna);
  result.fixes_enu = std::move(enu);
  return result;
}

}  // namespace uf
