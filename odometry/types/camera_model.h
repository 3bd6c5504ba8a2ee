// Camera projection models. Camera axes as OpenCV: x right, y down, z forward (optical axis); pixel
// (0, 0) is the centre of the top-left pixel. Intrinsics are in pixels; distortion coefficients unitless.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "odometry/types/pinhole_intrinsics.h"
#include "odometry/types/status.h"

namespace uf {

class CameraModel {
 public:
  virtual ~CameraModel() = default;

  int width() const { return width_; }
  int height() const { return height_; }

  // Pixel of a point in the camera frame, and optionally d(pixel)/d(p_cam). nullopt for a point behind the
  // camera (z <= kMinDepth) or outside the region where the distortion model is one-to-one. The pixel may
  // lie outside the image: see InImage.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_cam,
                                         Eigen::Matrix<double, 2, 3>* jacobian = nullptr) const;

  // Unit bearing (z >= 0) of the ray through a pixel; the distortion is inverted iteratively.
  virtual Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel) const = 0;

  // Error for impossible intrinsics (size <= 0, focal length not positive and finite, principal point
  // outside the image, non-finite distortion); the message names the field and its value.
  Status Validate() const;

  bool InImage(const Eigen::Vector2d& pixel) const;  // within [-0.5, width - 0.5] x [-0.5, height - 0.5]

  virtual std::unique_ptr<CameraModel> Clone() const = 0;

  static constexpr double kMinDepth = 1e-6;  // m

 protected:
  CameraModel(int width, int height) : width_(width), height_(height) {}

  // Project for a point with z > kMinDepth.
  virtual std::optional<Eigen::Vector2d> ProjectInFront(const Eigen::Vector3d& p_cam,
                                                        Eigen::Matrix<double, 2, 3>* jacobian) const = 0;
  virtual Status ValidateIntrinsics() const = 0;
  // Checks shared by every model: fx, fy positive and finite, (cx, cy) inside the image.
  Status ValidateFocalAndCentre(const PinholeIntrinsics& pinhole) const;

 private:
  int width_;
  int height_;
};

// Pinhole with radial-tangential ("plumb bob", OpenCV's default) distortion: for x = X/Z, y = Y/Z,
// r^2 = x^2 + y^2, the distorted point is
//   xd = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   yd = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
// and the pixel is (fx xd + cx, fy yd + cy). Points beyond the radius where the radial distortion
// r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing (it folds back) are not projected.
struct PinholeRadtanIntrinsics {
  PinholeIntrinsics pinhole;  // image size, fx, fy, cx, cy
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};

class PinholeRadtan : public CameraModel {
 public:
  explicit PinholeRadtan(const PinholeRadtanIntrinsics& intrinsics);

  const PinholeRadtanIntrinsics& intrinsics() const { return k_; }
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel) const override;
  std::unique_ptr<CameraModel> Clone() const override { return std::make_unique<PinholeRadtan>(*this); }

 protected:
  std::optional<Eigen::Vector2d> ProjectInFront(const Eigen::Vector3d& p_cam,
                                                Eigen::Matrix<double, 2, 3>* jacobian) const override;
  Status ValidateIntrinsics() const override;

 private:
  // Distorted normalised point of (x, y), and optionally its 2x2 Jacobian.
  Eigen::Vector2d Distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* jacobian) const;

  PinholeRadtanIntrinsics k_;
  double max_r2_;  // largest x^2 + y^2 up to which the radial distortion is increasing (may be infinite)
};

// Equidistant fisheye (Kannala-Brandt, OpenCV's fisheye model): for the angle theta between the ray and
// the optical axis, theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8), and the
// pixel is (fx theta_d X / rho + cx, fy theta_d Y / rho + cy) with rho = sqrt(X^2 + Y^2). Points beyond
// the angle where theta_d stops increasing are not projected.
struct EquidistantIntrinsics {
  PinholeIntrinsics pinhole;  // image size, fx, fy, cx, cy
  double k1 = 0, k2 = 0, k3 = 0, k4 = 0;
};

class Equidistant : public CameraModel {
 public:
  explicit Equidistant(const EquidistantIntrinsics& intrinsics);

  const EquidistantIntrinsics& intrinsics() const { return k_; }
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel) const override;
  std::unique_ptr<CameraModel> Clone() const override { return std::make_unique<Equidistant>(*this); }

 protected:
  std::optional<Eigen::Vector2d> ProjectInFront(const Eigen::Vector3d& p_cam,
                                                Eigen::Matrix<double, 2, 3>* jacobian) const override;
  Status ValidateIntrinsics() const override;

 private:
  EquidistantIntrinsics k_;
  double max_theta_;  // largest angle up to which theta_d is increasing, at most pi/2 (z > 0)
};

// The model's own size, focal lengths and principal point (its distortion dropped), and whether it has a
// non-zero distortion coefficient. Models other than PinholeRadtan and Equidistant: none.
std::optional<PinholeIntrinsics> PinholeOf(const CameraModel& model);
bool IsDistorted(const CameraModel& model);

}  // namespace uf
