#include "export/gnss_alignment.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace uf::exporting {
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
  Expected<Georeference> georef = Georeference::Create(result.origin);
  if (!georef) return georef.status();

  std::vector<Eigen::Vector3d> antenna, enu;
  std::vector<double> weight;
  for (const GnssFix& fix : fixes) {
    if (!HasPosition(fix)) continue;
    const std::optional<SE3> pose = trajectory.PoseAt(fix.stamp);
    if (!pose) continue;
    antenna.push_back(*pose * options.T_body_antenna.translation());
    enu.push_back(
        georef->GeodeticToEnu(Eigen::Vector3d(fix.latitude_deg, fix.longitude_deg, fix.altitude_m)));
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

  // Weighted centroids and cross-covariance (see the header).
  double total = 0;
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_f = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < antenna.size(); ++i) {
    total += weight[i];
    mean_a += weight[i] * antenna[i];
    mean_f += weight[i] * enu[i];
  }
  mean_a /= total;
  mean_f /= total;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (options.gravity_aligned) {
    double s = 0, c = 0;
    for (std::size_t i = 0; i < antenna.size(); ++i) {
      const Eigen::Vector3d a = antenna[i] - mean_a, f = enu[i] - mean_f;
      s += weight[i] * (a.x() * f.y() - a.y() * f.x());
      c += weight[i] * (a.x() * f.x() + a.y() * f.y());
    }
    R = Eigen::AngleAxisd(std::atan2(s, c), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  } else {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // sum w f a^T
    for (std::size_t i = 0; i < antenna.size(); ++i)
      H += weight[i] * (enu[i] - mean_f) * (antenna[i] - mean_a).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
    R = svd.matrixU() * D * svd.matrixV().transpose();
  }
  result.T_enu_world = SE3(SO3(R), mean_f - R * mean_a);
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

}  // namespace uf::exporting
