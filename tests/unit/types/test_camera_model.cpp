#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <vector>

#include "odometry/types/camera_model.h"
#include "tests/unit/types/numeric_jacobian.h"

namespace uf {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using test::NumericJacobian;

constexpr double kProjectionJacobianStep = 1e-5;       // m
constexpr double kProjectionJacobianTolerance = 1e-5;  // px/m (see numeric_jacobian.h)

// EuRoC MAV cam0 (radial-tangential) and TUM-VI cam0 (equidistant) calibrations.
PinholeRadtan EurocCamera() {
  return PinholeRadtan(
      {.pinhole = {.width = 752, .height = 480, .fx = 458.654, .fy = 457.296, .cx = 367.215, .cy = 248.375},
       .k1 = -0.28340811,
       .k2 = 0.07395907,
       .p1 = 0.00019359,
       .p2 = 1.76187114e-05,
       .k3 = 0.0});
}

Equidistant TumViCamera() {
  return Equidistant(
      {.pinhole = {.width = 512, .height = 512, .fx = 190.978, .fy = 190.973, .cx = 254.932, .cy = 256.897},
       .k1 = 0.0034823894,
       .k2 = 0.000715035,
       .k3 = -0.0020532361,
       .k4 = 0.000202936});
}

// Points in front of the camera: on the axis, near it, generic, and at wide angles (70 degrees for the
// fisheye; within the EuRoC field of view for the pinhole).
std::vector<Vector3d> TestPoints(bool wide) {
  std::vector<Vector3d> points = {Vector3d(0, 0, 2), Vector3d(1e-12, -1e-12, 1.5), Vector3d(1e-6, 2e-6, 1.0),
                                  Vector3d(0.3, -0.2, 1.0), Vector3d(-0.5, 0.4, 2.5)};
  if (wide) {
    const double angle = 70.0 * std::numbers::pi / 180.0;
    points.push_back(Vector3d(std::sin(angle) * 0.6, std::sin(angle) * 0.8, std::cos(angle)) * 3.0);
  } else {
    points.push_back(Vector3d(-0.75, -0.5, 1.0));
  }
  return points;
}

void ExpectProjectJacobianMatchesNumeric(const CameraModel& camera, const std::vector<Vector3d>& points) {
  for (const Vector3d& p : points) {
    Eigen::Matrix<double, 2, 3> analytic;
    ASSERT_TRUE(camera.Project(p, &analytic).has_value()) << p.transpose();
    const auto f = [&](const Vector3d& q) { return Vector2d(*camera.Project(q)); };
    const Eigen::Matrix<double, 2, 3> numeric = NumericJacobian<2, 3>(f, p, kProjectionJacobianStep);
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), kProjectionJacobianTolerance) << p.transpose();
  }
}

// Every 16th pixel of the image within max_radius of the image centre: pixel -> bearing -> pixel, and the
// bearing is a unit vector that projects back to the same pixel at any depth.
void ExpectUnprojectInvertsProject(const CameraModel& camera, double max_radius) {
  const Vector2d centre(0.5 * camera.width(), 0.5 * camera.height());
  int tested = 0;
  for (int v = 0; v < camera.height(); v += camera.height() / 16) {
    for (int u = 0; u < camera.width(); u += camera.width() / 16) {
      const Vector2d pixel(u, v);
      if ((pixel - centre).norm() > max_radius) continue;
      ++tested;
      const Vector3d bearing = camera.Unproject(pixel);
      EXPECT_NEAR(bearing.norm(), 1.0, 1e-15);
      for (double depth : {0.5, 7.0}) {
        const std::optional<Vector2d> back = camera.Project(depth * bearing);
        ASSERT_TRUE(back.has_value()) << pixel.transpose();
        EXPECT_LT((*back - pixel).norm(), 1e-9) << pixel.transpose();
      }
    }
  }
  EXPECT_GT(tested, 100);
}

TEST(CameraModelTest, PinholeWithoutDistortionMatchesHandComputation) {
  const PinholeRadtan camera(
      {.pinhole = {.width = 640, .height = 480, .fx = 500, .fy = 400, .cx = 320, .cy = 240}});
  // (500 * 1/4 + 320, 400 * 2/4 + 240)
  EXPECT_TRUE(camera.Project(Vector3d(1, 2, 4))->isApprox(Vector2d(445, 440)));
  EXPECT_TRUE(camera.Unproject(Vector2d(445, 440)).isApprox(Vector3d(1, 2, 4).normalized()));
}

TEST(CameraModelTest, EquidistantWithoutDistortionMatchesHandComputation) {
  const Equidistant camera(
      {.pinhole = {.width = 640, .height = 480, .fx = 300, .fy = 300, .cx = 320, .cy = 240}});
  // 45 degrees off axis along x: theta_d = pi/4, so u = cx + fx pi/4.
  EXPECT_TRUE(camera.Project(Vector3d(2, 0, 2))->isApprox(Vector2d(320 + 300 * std::numbers::pi / 4, 240)));
}

TEST(CameraModelTest, PinholeRadtanProjectJacobianMatchesNumeric) {
  ExpectProjectJacobianMatchesNumeric(EurocCamera(), TestPoints(false));
  // Strong tangential and k3 terms exercise every entry of the distortion Jacobian.
  const PinholeRadtan strong(
      {.pinhole = {.width = 640, .height = 480, .fx = 400, .fy = 420, .cx = 330, .cy = 230},
       .k1 = -0.2,
       .k2 = 0.05,
       .p1 = 0.01,
       .p2 = -0.02,
       .k3 = 0.01});
  ExpectProjectJacobianMatchesNumeric(strong, TestPoints(false));
}

TEST(CameraModelTest, EquidistantProjectJacobianMatchesNumeric) {
  ExpectProjectJacobianMatchesNumeric(TumViCamera(), TestPoints(true));
  const Equidistant strong(
      {.pinhole = {.width = 640, .height = 480, .fx = 250, .fy = 260, .cx = 320, .cy = 240},
       .k1 = -0.05,
       .k2 = 0.01,
       .k3 = -0.002,
       .k4 = 0.0005});
  ExpectProjectJacobianMatchesNumeric(strong, TestPoints(true));
}

TEST(CameraModelTest, PinholeRadtanUnprojectInvertsProject) {
  ExpectUnprojectInvertsProject(EurocCamera(), 1e9);  // the whole image, corners included
}

TEST(CameraModelTest, EquidistantUnprojectInvertsProject) {
  // The TUM-VI corners look more than 90 degrees off axis (z < 0), which Project rejects by design; the
  // inscribed circle of radius 250 px reaches theta ~ 1.31 rad = 75 degrees.
  ExpectUnprojectInvertsProject(TumViCamera(), 250.0);
}

TEST(CameraModelTest, ProjectThenUnprojectGivesTheBearing) {
  const PinholeRadtan pinhole = EurocCamera();
  const Equidistant fisheye = TumViCamera();
  for (const Vector3d& p : {Vector3d(0.3, -0.2, 1.0), Vector3d(-0.5, 0.4, 2.5), Vector3d(0, 0, 3)}) {
    EXPECT_LT((pinhole.Unproject(*pinhole.Project(p)) - p.normalized()).norm(), 1e-12);
    EXPECT_LT((fisheye.Unproject(*fisheye.Project(p)) - p.normalized()).norm(), 1e-12);
  }
}

TEST(CameraModelTest, PointsBehindTheCameraAreNotProjected) {
  const PinholeRadtan pinhole = EurocCamera();
  const Equidistant fisheye = TumViCamera();
  for (const Vector3d& p : {Vector3d(0, 0, 0), Vector3d(0.1, 0.2, -1.0), Vector3d(1, 0, 0)}) {
    EXPECT_FALSE(pinhole.Project(p).has_value()) << p.transpose();
    EXPECT_FALSE(fisheye.Project(p).has_value()) << p.transpose();
  }
  EXPECT_FALSE(pinhole.Project(Vector3d(0, 0, std::nan(""))).has_value());
}

TEST(CameraModelTest, PointsPastTheDistortionFoldAreNotProjected) {
  // r (1 - 0.5 r^2) increases only up to r^2 = 2/3 (r = 0.816).
  const PinholeRadtan pinhole(
      {.pinhole = {.width = 640, .height = 480, .fx = 400, .fy = 400, .cx = 320, .cy = 240}, .k1 = -0.5});
  EXPECT_TRUE(pinhole.Project(Vector3d(0.8, 0.0, 1.0)).has_value());
  EXPECT_FALSE(pinhole.Project(Vector3d(0.82, 0.0, 1.0)).has_value());
  // theta (1 - 0.2 theta^2) increases only up to theta^2 = 1/0.6 (theta = 1.291 rad = 74 degrees).
  const Equidistant fisheye(
      {.pinhole = {.width = 640, .height = 480, .fx = 200, .fy = 200, .cx = 320, .cy = 240}, .k1 = -0.2});
  const auto at_angle = [](double degrees) {
    const double a = degrees * std::numbers::pi / 180.0;
    return Vector3d(0.0, std::sin(a), std::cos(a));
  };
  EXPECT_TRUE(fisheye.Project(at_angle(73.5)).has_value());
  EXPECT_FALSE(fisheye.Project(at_angle(74.5)).has_value());
}

TEST(CameraModelTest, InImageAndClone) {
  const Equidistant camera = TumViCamera();
  EXPECT_TRUE(camera.InImage(Vector2d(0, 0)));
  EXPECT_TRUE(camera.InImage(Vector2d(511.4, 511.4)));
  EXPECT_FALSE(camera.InImage(Vector2d(-0.6, 10)));
  EXPECT_FALSE(camera.InImage(Vector2d(10, 511.6)));
  const std::unique_ptr<CameraModel> copy = camera.Clone();
  EXPECT_EQ(copy->width(), 512);
  EXPECT_EQ(*copy->Project(Vector3d(0.1, 0.2, 1.0)), *camera.Project(Vector3d(0.1, 0.2, 1.0)));
}

// Validate must fail, and its message must name the field and the value.
void ExpectInvalid(const CameraModel& camera, const std::string& field_and_value) {
  const Status status = camera.Validate();
  ASSERT_FALSE(status.ok()) << field_and_value;
  EXPECT_NE(status.message().find(field_and_value), std::string::npos) << status.message();
}

TEST(CameraModelTest, ValidateAcceptsRealCalibrations) {
  EXPECT_TRUE(EurocCamera().Validate().ok());
  EXPECT_TRUE(TumViCamera().Validate().ok());
}

TEST(CameraModelTest, ValidateNamesTheImpossibleField) {
  const PinholeRadtanIntrinsics good{
      .pinhole = {.width = 640, .height = 480, .fx = 400, .fy = 400, .cx = 320, .cy = 240}};
  PinholeRadtanIntrinsics k = good;
  k.pinhole.width = 0;
  ExpectInvalid(PinholeRadtan(k), "width = 0");
  k = good;
  k.pinhole.height = -3;
  ExpectInvalid(PinholeRadtan(k), "height = -3");
  k = good;
  k.pinhole.fx = -5;
  ExpectInvalid(PinholeRadtan(k), "fx = -5");
  k = good;
  k.pinhole.fy = std::nan("");
  ExpectInvalid(PinholeRadtan(k), "fy = nan");
  k = good;
  k.pinhole.fx = 0;
  ExpectInvalid(PinholeRadtan(k), "fx = 0");
  k = good;
  k.pinhole.cx = 700;
  ExpectInvalid(PinholeRadtan(k), "cx = 700");
  k = good;
  k.pinhole.cy = -20;
  ExpectInvalid(PinholeRadtan(k), "cy = -20");
  k = good;
  k.p2 = std::numeric_limits<double>::infinity();
  ExpectInvalid(PinholeRadtan(k), "p2 = inf");

  ExpectInvalid(Equidistant({.pinhole = {.width = 640,
                                         .height = 480,
                                         .fx = 200,
                                         .fy = std::numeric_limits<double>::infinity(),
                                         .cx = 320,
                                         .cy = 240}}),
                "fy = inf");
  ExpectInvalid(
      Equidistant({.pinhole = {.width = 640, .height = 480, .fx = 200, .fy = 200, .cx = 320, .cy = 240},
                   .k4 = std::nan("")}),
      "k4 = nan");
}

// A model that is neither pinhole-radtan nor equidistant (an orthographic camera, for the test only).
class Orthographic : public CameraModel {
 public:
  Orthographic() : CameraModel(4, 3) {}
  Eigen::Vector3d Unproject(const Eigen::Vector2d&) const override { return Eigen::Vector3d::UnitZ(); }
  std::unique_ptr<CameraModel> Clone() const override { return std::make_unique<Orthographic>(*this); }

 protected:
  std::optional<Eigen::Vector2d> ProjectInFront(const Eigen::Vector3d& p,
                                                Eigen::Matrix<double, 2, 3>*) const override {
    return Eigen::Vector2d(p.x(), p.y());
  }
  Status ValidateIntrinsics() const override { return {}; }
};

TEST(CameraModel, ThePinholeOfAModelIsItsSizeFocalLengthsAndPrincipalPoint) {
  PinholeRadtanIntrinsics radtan;
  radtan.pinhole = {.width = 640, .height = 480, .fx = 400, .fy = 410, .cx = 319.5, .cy = 239.25};
  radtan.k2 = 0.01;
  EXPECT_EQ(PinholeOf(PinholeRadtan(radtan)), (PinholeIntrinsics{640, 480, 400, 410, 319.5, 239.25}));
  EXPECT_TRUE(IsDistorted(PinholeRadtan(radtan)));  // k2 alone is a distortion

  // A fisheye keeps its focal lengths and principal point, and is always distorted, even without
  // coefficients (its projection is not a pinhole's).
  const Equidistant fisheye(EquidistantIntrinsics{{1280, 1024, 350, 350.5, 640.1, 511.9}});
  EXPECT_EQ(PinholeOf(fisheye), (PinholeIntrinsics{1280, 1024, 350, 350.5, 640.1, 511.9}));
  EXPECT_TRUE(IsDistorted(fisheye));

  EXPECT_FALSE(PinholeOf(Orthographic()).has_value());
}

}  // namespace
}  // namespace uf
