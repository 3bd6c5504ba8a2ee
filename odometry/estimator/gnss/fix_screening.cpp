#include "odometry/estimator/gnss/fix_screening.h"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <cmath>
#include <sstream>

namespace uf::estimator {
namespace {

template <typename... Parts>
std::string Text(const Parts&... parts) {
  std::ostringstream out;
  out.precision(12);
  (out << ... << parts);
  return out.str();
}

constexpr double kMinAltitudeM = -12e3, kMaxAltitudeM = 100e3;  // as ValidateGeodeticOrigin

std::optional<std::string> ScreenPosition(const GnssFix& fix) {
  if (!std::isfinite(fix.latitude_deg) || !std::isfinite(fix.longitude_deg) || !std::isfinite(fix.altitude_m))
    return Text("non-finite position (latitude ", fix.latitude_deg, ", longitude ", fix.longitude_deg,
                ", altitude ", fix.altitude_m, ")");
  if (std::abs(fix.latitude_deg) > 90)
    return Text("latitude ", fix.latitude_deg, " deg is outside [-90, 90]");
  if (std::abs(fix.longitude_deg) > 180)
    return Text("longitude ", fix.longitude_deg, " deg is outside [-180, 180]");
  if (fix.altitude_m < kMinAltitudeM || fix.altitude_m > kMaxAltitudeM)
    return Text("altitude ", fix.altitude_m, " m is outside [-12000, 100000]");
  return std::nullopt;
}

std::optional<std::string> ScreenCovariance(const Eigen::Matrix3d& C, bool allow_unknown) {
  if (!C.allFinite()) return std::string("non-finite covariance");
  if (C.isZero(0.0)) {
    if (allow_unknown) return std::nullopt;
    return std::string("all-zero covariance (accuracy unknown)");
  }
  const double scale = C.cwiseAbs().maxCoeff();
  if ((C - C.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    return std::string("covariance not symmetric");
  const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues();
  if (eigenvalues.minCoeff() < -1e-12 * std::max(scale, 1.0))
    return Text("covariance not positive semidefinite (smallest eigenvalue ", eigenvalues.minCoeff(),
                " m^2)");
  return std::nullopt;
}

}  // namespace

bool HasUnknownCovariance(const GnssFix& fix) { return fix.covariance_enu.isZero(0.0); }

std::optional<std::string> ScreenFix(const GnssFix& fix, const GnssFactorConfig& config) {
  if (fix.status == GnssFixStatus::kNoFix) return std::string("no fix");
  if (static_cast<int>(fix.status) < static_cast<int>(config.min_status))
    return Text("status ", GnssStatusName(fix.status), " is below the minimum ",
                GnssStatusName(config.min_status));
  if (auto why = ScreenPosition(fix)) return why;
  return ScreenCovariance(fix.covariance_enu, config.use_nominal_for_unknown);
}

Eigen::Matrix3d FixCovariance(const GnssFix& fix, const GnssFactorConfig& config) {
  assert(!ScreenFix(fix, config));
  const GnssStatusNoise& noise = config.Noise(fix.status);
  Eigen::Matrix3d S = 0.5 * (fix.covariance_enu + fix.covariance_enu.transpose());
  if (HasUnknownCovariance(fix)) {
    const double h2 = noise.nominal_horizontal_sigma_m * noise.nominal_horizontal_sigma_m;
    S = Eigen::Vector3d(h2, h2, noise.nominal_vertical_sigma_m * noise.nominal_vertical_sigma_m).asDiagonal();
  }
  S *= noise.sigma_scale * noise.sigma_scale;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(S);
  const Eigen::Vector3d floored = eigen.eigenvalues().cwiseMax(noise.min_sigma_m * noise.min_sigma_m);
  const Eigen::Matrix3d floored_S =
      eigen.eigenvectors() * floored.asDiagonal() * eigen.eigenvectors().transpose();
  return 0.5 * (floored_S + floored_S.transpose());
}

}  // namespace uf::estimator
