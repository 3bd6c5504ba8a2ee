#include "odometry/eval/gnss_alignment.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "odometry/types/alignment.h"

namespace uf {
namespace {

bool HasPosition(const GnssFix& fix) {
  return fix.status != GnssFixStatus::kNoFix && std::isfinite(fix.latitude_deg) &&
         std::isfinite(fix.longitude_deg) && std::isfinite(fix.altitude_m) && fix.covariance_enu.allFinite();
}

}  // namespace

Expected<GnssAlignment> AlignToGnss(const Trajectory& trajectory, std::span<const GnssFix> fixes,
                                    const GnssAlignmentOptions& options) {
  const auto first = std::find_if(fixes.begin(), fixes.end(), HasPosition);
  if (first == fixes.end()) return Status::Error("GNSS alignment: no fix with a position");
  GnssAlignment result;
  result.origin = {first->latitude_deg, first->longitude_deg, first->altitude_m};
  Expected<EnuFrame> enu_frame = EnuFrame::Create(result.origin);
  if (!enu_frame) return Status::Error("GNSS alignment: first fix: " + enu_frame.error());

  std::vector<Eigen::Vector3d> antenna, enu;
  std::vector<double> weight;
  for (const GnssFix& fix : fixes) {
    if (!HasPosition(fix)) continue;
    const std::optional<SE3> pose = trajectory.PoseAt(fix.stamp);
    if (!pose) continue;
    antenna.push_back(*pose * options.T_body_antenna.translation());
    enu.push_back(
        enu_frame->EnuFromGeodetic(Eigen::Vector3d(fix.latitude_deg, fix.longitude_deg, fix.altitude_m)));
    weight.push_back(1.0 / std::max(fix.covariance_enu.trace() / 3.0, 1e-6));
  }
  result.fixes_used = static_cast<int>(antenna.size());
  if (result.fixes_used < options.min_fixes)
    return Status::Error("GNSS alignment: " + std::to_string(result.fixes_used) +
                         " fixes within the trajectory's time span, need " +
                         std::to_string(options.min_fixes));
  double extent = 0;
  for (const Eigen::Vector3d& a : antenna) extent = std::max(extent, (a - antenna.front()).norm());
  if (extent < options.min_extent_m) {
    std::ostringstream why;
    why << "GNSS alignment: the trajectory spans " << extent << " m at the fixes, need "
        << options.min_extent_m << " m for the heading";
    return Status::Error(why.str());
  }

  result.T_enu_world = WeightedRigidAlignment(antenna, enu, weight, options.gravity_aligned);
  double squared = 0;
  for (std::size_t i = 0; i < antenna.size(); ++i)
    squared += (result.T_enu_world * antenna[i] - enu[i]).squaredNorm();
  result.rms_m = std::sqrt(squared / static_cast<double>(antenna.size()));
  if (result.rms_m > options.max_rms_m) {
    std::ostringstream why;
    why << "GNSS alignment: residual RMS " << result.rms_m << " m exceeds " << options.max_rms_m << " m";
    return Status::Error(why.str());
  }
  return result;
}

}  // namespace uf
