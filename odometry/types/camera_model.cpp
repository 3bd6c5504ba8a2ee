#include "odometry/types/camera_model.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

namespace uf {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Status FieldError(const char* field, double value, const char* requirement) {
  std::ostringstream message;
  message.precision(12);
  message << "camera intrinsics: " << field << " = " << value << " " << requirement;
  return Status::Error(message.str());
}

// Smallest s in (0, s_max] with derivative(s) <= 0, or infinity if there is none. derivative(0) = 1 for the
// distortion profiles here; s is sampled on a geometric grid (steps of 0.5%, so a dip narrower than that is
// missed) and the sign change is refined by bisection.
template <typename Function>
double FirstNonIncreasing(Function derivative, double s_min, double s_max) {
  double previous = 0.0;
  for (double s = s_min; s <= s_max; s *= 1.005) {
    if (!(derivative(s) > 0.0)) {
      double lo = previous, hi = s;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (derivative(mid) > 0.0 ? lo : hi) = mid;
      }
      return lo;
    }
    previous = s;
  }
  return kInfinity;
}

}  // namespace

// ---- CameraModel ----

std::optional<Eigen::Vector2d> CameraModel::Project(const Eigen::Vector3d& p_cam,
                                                    Eigen::Matrix<double, 2, 3>* jacobian) const {
  if (!(p_cam.z() > kMinDepth)) return std::nullopt;  // behind the camera (or NaN)
  return ProjectInFront(p_cam, jacobian);
}

Status CameraModel::Validate() const {
  if (width_ <= 0) return FieldError("width", width_, "must be positive");
  if (height_ <= 0) return FieldError("height", height_, "must be positive");
  return ValidateIntrinsics();
}

bool CameraModel::InImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() <= width_ - 0.5 && pixel.y() >= -0.5 && pixel.y() <= height_ - 0.5;
}

Status CameraModel::ValidateFocalAndCentre(const PinholeIntrinsics& pinhole) const {
  const double fx = pinhole.fx, fy = pinhole.fy, cx = pinhole.cx, cy = pinhole.cy;
  if (!(std::isfinite(fx) && fx > 0.0)) return FieldError("fx", fx, "must be positive and finite");
  if (!(std::isfinite(fy) && fy > 0.0)) return FieldError("fy", fy, "must be positive and finite");
  if (!(cx >= -0.5 && cx <= width_ - 0.5)) return FieldError("cx", cx, "must lie inside the image width");
  if (!(cy >= -0.5 && cy <= height_ - 0.5)) return FieldError("cy", cy, "must lie inside the image height");
  return Status();
}

// ---- PinholeRadtan ----

PinholeRadtan::PinholeRadtan(const PinholeRadtanIntrinsics& intrinsics)
    : CameraModel(intrinsics.pinhole.width, intrinsics.pinhole.height), k_(intrinsics) {
  // d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)] = 1 + 3 k1 s + 5 k2 s^2 + 7 k3 s^3 with s = r^2.
  const auto derivative = [this](double s) {
    return 1.0 + s * (3.0 * k_.k1 + s * (5.0 * k_.k2 + s * 7.0 * k_.k3));
  };
  max_r2_ = FirstNonIncreasing(derivative, 1e-4, 1e8);
}

Eigen::Vector2d PinholeRadtan::Distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* jacobian) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k_.k1 + r2 * (k_.k2 + r2 * k_.k3));
  const Eigen::Vector2d distorted(x * radial + 2.0 * k_.p1 * x * y + k_.p2 * (r2 + 2.0 * x * x),
                                  y * radial + k_.p1 * (r2 + 2.0 * y * y) + 2.0 * k_.p2 * x * y);
  if (jacobian != nullptr) {
    // d(radial)/d(r^2) = k1 + 2 k2 r^2 + 3 k3 r^4, and d(r^2)/dx = 2x, d(r^2)/dy = 2y.
    const double d_radial = k_.k1 + r2 * (2.0 * k_.k2 + r2 * 3.0 * k_.k3);
    *jacobian << radial + 2.0 * x * x * d_radial + 2.0 * k_.p1 * y + 6.0 * k_.p2 * x,
        2.0 * x * y * d_radial + 2.0 * k_.p1 * x + 2.0 * k_.p2 * y,
        2.0 * x * y * d_radial + 2.0 * k_.p1 * x + 2.0 * k_.p2 * y,
        radial + 2.0 * y * y * d_radial + 6.0 * k_.p1 * y + 2.0 * k_.p2 * x;
  }
  return distorted;
}

std::optional<Eigen::Vector2d> PinholeRadtan::ProjectInFront(const Eigen::Vector3d& p_cam,
                                                             Eigen::Matrix<double, 2, 3>* jacobian) const {
  const PinholeIntrinsics& p = k_.pinhole;
  const double inv_z = 1.0 / p_cam.z();
  const Eigen::Vector2d xy(p_cam.x() * inv_z, p_cam.y() * inv_z);
  if (!(xy.squaredNorm() <= max_r2_)) return std::nullopt;  // past the fold of the distortion
  Eigen::Matrix2d d_distorted_d_xy;
  const Eigen::Vector2d distorted = Distort(xy, jacobian != nullptr ? &d_distorted_d_xy : nullptr);
  if (jacobian != nullptr) {
    // pixel = diag(fx, fy) distort(x, y), with d(x, y)/d(X, Y, Z) = [1/Z 0 -x/Z; 0 1/Z -y/Z].
    Eigen::Matrix<double, 2, 3> d_xy_d_p;
    d_xy_d_p << inv_z, 0.0, -xy.x() * inv_z,  //
        0.0, inv_z, -xy.y() * inv_z;
    *jacobian = Eigen::Vector2d(p.fx, p.fy).asDiagonal() * d_distorted_d_xy * d_xy_d_p;
  }
  return Eigen::Vector2d(p.fx * distorted.x() + p.cx, p.fy * distorted.y() + p.cy);
}

Eigen::Vector3d PinholeRadtan::Unproject(const Eigen::Vector2d& pixel) const {
  const PinholeIntrinsics& p = k_.pinhole;
  // Solve Distort(x, y) = target by Newton's method, starting from the distorted point itself.
  const Eigen::Vector2d target((pixel.x() - p.cx) / p.fx, (pixel.y() - p.cy) / p.fy);
  Eigen::Vector2d xy = target;
  for (int iteration = 0; iteration < 50; ++iteration) {
    Eigen::Matrix2d jacobian;
    const Eigen::Vector2d residual = Distort(xy, &jacobian) - target;
    const Eigen::Vector2d step = jacobian.inverse() * residual;
    if (!step.allFinite()) break;
    xy -= step;
    if (step.squaredNorm() < 1e-30 * (1.0 + xy.squaredNorm())) break;
  }
  return Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
}

Status PinholeRadtan::ValidateIntrinsics() const {
  if (Status status = ValidateFocalAndCentre(k_.pinhole); !status.ok()) return status;
  for (const auto& [name, value] : {std::pair{"k1", k_.k1}, std::pair{"k2", k_.k2}, std::pair{"p1", k_.p1},
                                    std::pair{"p2", k_.p2}, std::pair{"k3", k_.k3}}) {
    if (!std::isfinite(value)) return FieldError(name, value, "must be finite");
  }
  return Status();
}

// ---- Equidistant ----

namespace {

// theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8) and its derivative in theta.
struct DistortedAngle {
  double theta_d;
  double derivative;
};

DistortedAngle Distortion(const EquidistantIntrinsics& k, double theta) {
  const double t2 = theta * theta;
  const double poly = 1.0 + t2 * (k.k1 + t2 * (k.k2 + t2 * (k.k3 + t2 * k.k4)));
  const double derivative = 1.0 + t2 * (3.0 * k.k1 + t2 * (5.0 * k.k2 + t2 * (7.0 * k.k3 + t2 * 9.0 * k.k4)));
  return {theta * poly, derivative};
}

}  // namespace

Equidistant::Equidistant(const EquidistantIntrinsics& intrinsics)
    : CameraModel(intrinsics.pinhole.width, intrinsics.pinhole.height), k_(intrinsics) {
  const auto derivative = [this](double theta) { return Distortion(k_, theta).derivative; };
  max_theta_ = std::min(FirstNonIncreasing(derivative, 1e-3, std::numbers::pi / 2), std::numbers::pi / 2);
}

std::optional<Eigen::Vector2d> Equidistant::ProjectInFront(const Eigen::Vector3d& p_cam,
                                                           Eigen::Matrix<double, 2, 3>* jacobian) const {
  const PinholeIntrinsics& p = k_.pinhole;
  const double X = p_cam.x(), Y = p_cam.y(), Z = p_cam.z();
  const double rho2 = X * X + Y * Y;
  const double rho = std::sqrt(rho2);
  const double theta = std::atan2(rho, Z);
  if (!(theta <= max_theta_)) return std::nullopt;  // past the fold of the distortion
  if (rho < 1e-9 * Z) {
    // On the optical axis theta_d / rho -> 1 / Z: the pinhole limit (neglected terms are O((rho/Z)^2)).
    if (jacobian != nullptr) {
      *jacobian << p.fx / Z, 0.0, -p.fx * X / (Z * Z),  //
          0.0, p.fy / Z, -p.fy * Y / (Z * Z);
    }
    return Eigen::Vector2d(p.fx * X / Z + p.cx, p.fy * Y / Z + p.cy);
  }
  const DistortedAngle d = Distortion(k_, theta);
  const double scale = d.theta_d / rho;  // pixel = diag(fx, fy) scale (X, Y) + (cx, cy)
  if (jacobian != nullptr) {
    // d(theta)/dX = Z X / (rho (rho^2 + Z^2)), d(theta)/dZ = -rho / (rho^2 + Z^2), d(rho)/dX = X / rho, so
    // d(scale)/dX = X c and d(scale)/dY = Y c with c = theta_d' Z / (rho^2 (rho^2 + Z^2)) - theta_d / rho^3,
    // and d(scale)/dZ = -theta_d' / (rho^2 + Z^2).
    const double norm2 = rho2 + Z * Z;
    const double c = d.derivative * Z / (rho2 * norm2) - d.theta_d / (rho2 * rho);
    const double d_scale_d_z = -d.derivative / norm2;
    *jacobian << p.fx * (scale + X * X * c), p.fx * X * Y * c, p.fx * X * d_scale_d_z,  //
        p.fy * X * Y * c, p.fy * (scale + Y * Y * c), p.fy * Y * d_scale_d_z;
  }
  return Eigen::Vector2d(p.fx * scale * X + p.cx, p.fy * scale * Y + p.cy);
}

Eigen::Vector3d Equidistant::Unproject(const Eigen::Vector2d& pixel) const {
  const PinholeIntrinsics& p = k_.pinhole;
  // The pixel gives theta_d and the direction in the image plane; theta solves theta_d(theta) = theta_d
  // by Newton's method, kept inside [0, max_theta] where theta_d is increasing.
  const Eigen::Vector2d m((pixel.x() - p.cx) / p.fx, (pixel.y() - p.cy) / p.fy);
  const double theta_d = m.norm();
  if (theta_d < 1e-12) return Eigen::Vector3d(m.x(), m.y(), 1.0).normalized();
  double theta = std::min(theta_d, max_theta_);
  for (int iteration = 0; iteration < 50; ++iteration) {
    const DistortedAngle d = Distortion(k_, theta);
    const double step = (d.theta_d - theta_d) / d.derivative;
    if (!std::isfinite(step)) break;
    theta = std::clamp(theta - step, 0.0, max_theta_);
    if (std::abs(step) < 1e-15) break;
  }
  const double sin_over_theta_d = std::sin(theta) / theta_d;
  return Eigen::Vector3d(sin_over_theta_d * m.x(), sin_over_theta_d * m.y(), std::cos(theta));
}

Status Equidistant::ValidateIntrinsics() const {
  if (Status status = ValidateFocalAndCentre(k_.pinhole); !status.ok()) return status;
  for (const auto& [name, value] :
       {std::pair{"k1", k_.k1}, std::pair{"k2", k_.k2}, std::pair{"k3", k_.k3}, std::pair{"k4", k_.k4}}) {
    if (!std::isfinite(value)) return FieldError(name, value, "must be finite");
  }
  return Status();
}

std::optional<PinholeIntrinsics> PinholeOf(const CameraModel& model) {
  if (const auto* radtan = dynamic_cast<const PinholeRadtan*>(&model)) return radtan->intrinsics().pinhole;
  if (const auto* fisheye = dynamic_cast<const Equidistant*>(&model)) return fisheye->intrinsics().pinhole;
  return std::nullopt;
}

bool IsDistorted(const CameraModel& model) {
  if (const auto* radtan = dynamic_cast<const PinholeRadtan*>(&model)) {
    const PinholeRadtanIntrinsics& k = radtan->intrinsics();
    return k.k1 != 0 || k.k2 != 0 || k.p1 != 0 || k.p2 != 0 || k.k3 != 0;
  }
  return true;  // a fisheye is never a pinhole
}

}  // namespace uf
