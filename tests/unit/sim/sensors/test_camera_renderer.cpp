// Tests of the simulated camera's image formation (CameraRenderer): each pixel's rays against the camera
// model's independent projection, rendered checkerboard corners against OpenCV's sub-pixel corner finder,
// Lambert shading and the sky.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "odometry/sim/sensors/camera_renderer.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "tests/unit/sim/sensors/camera_test_support.h"
#include "tests/unit/sim/sensors/sensor_test_scenes.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf::sim {
namespace {

using namespace camera_test;  // NOLINT: the helpers of these tests

// ---- Geometry: each sub-sample's ray hits a point that the camera model projects back onto the pixel ----

TEST(CameraRenderer, RaysHitPointsThatProjectBackOntoTheirPixels) {
  const Scene scene = test::BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  const TrajectorySpline spline = uf::test::RandomSpline(3, 12, kSecond / 2);
  const SE3 T_body_camera(SO3::Exp(Eigen::Vector3d(0.3, -1.2, 0.5)), Eigen::Vector3d(0.4, -0.1, 0.25));
  for (const bool distorted : {false, true}) {
    CameraConfig config;
    config.pinhole = {.width = 320, .height = 240, .fx = 210, .fy = 200, .cx = 161.3, .cy = 118.2};
    config.supersampling = 3;
    if (distorted)
      config.k1 = -0.25, config.k2 = 0.08, config.p1 = 1e-3, config.p2 = -5e-4, config.k3 = -0.01;
    const CameraRenderer renderer = MakeRenderer(config, *caster, spline, T_body_camera);
    const PinholeRadtan model = CameraModelOf(config);
    std::mt19937 engine(11);
    double worst = 0.0;
    int checked = 0;
    for (double seconds : {0.1, 2.37, 4.45}) {
      const Stamp t = spline.begin() + FromSeconds(seconds);
      // Independent composition of the pose: T_world_camera = T_world_body T_body_camera.
      const SE3 T_camera_world = (spline.Evaluate(t).T_world_body * T_body_camera).inverse();
      for (int row : {0, 37, 119, 200, 239}) {
        auto rays = renderer.RowRays(t, row);
        ASSERT_TRUE(rays.ok());
        ASSERT_EQ(rays->size(), static_cast<std::size_t>(9 * config.pinhole.width));
        for (int k = 0; k < 60; ++k) {
          const int sy = std::uniform_int_distribution<int>(0, 2)(engine);
          const int u = k == 0   ? 0
                        : k == 1 ? config.pinhole.width - 1
                                 : std::uniform_int_distribution<int>(0, 319)(engine);
          const int sx = std::uniform_int_distribution<int>(0, 2)(engine);
          const Ray& ray = (*rays)[static_cast<std::size_t>((sy * config.pinhole.width + u) * 3 + sx)];
          const RayHit hit = caster->Cast(ray);
          ASSERT_TRUE(hit.hit());  // a closed room
          const Eigen::Vector3d X =
              ray.origin.cast<double>() + double(hit.distance) * ray.direction.cast<double>();
          const auto pixel = model.Project(T_camera_world * X);
          ASSERT_TRUE(pixel.has_value());
          const Eigen::Vector2d expected(u - 0.5 + (sx + 0.5) / 3.0, row - 0.5 + (sy + 0.5) / 3.0);
          worst = std::max(worst, (*pixel - expected).norm());
          ++checked;
        }
      }
    }
    EXPECT_EQ(checked, 3 * 5 * 60);
    EXPECT_LT(worst, 0.1) << "distorted " << distorted;
    EXPECT_LT(worst, 0.01) << "distorted " << distorted;  // float rays: far tighter than the requirement
  }
}

// Above 2^22 sub-samples the bearings are not cached but computed per row: the rays must be the same, i.e.
// R_world_camera times the model's own Unproject of the sub-sample's pixel.
TEST(CameraRenderer, LargeImagesComputeTheSameRaysWithoutTheBearingCache) {
  const Scene scene = test::BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  const TrajectorySpline spline = uf::test::RandomSpline(4, 8, kSecond / 2);
  CameraConfig config;
  config.pinhole = {.width = 1200, .height = 1000, .fx = 700, .fy = 700, .cx = 600, .cy = 499};
  config.k1 = -0.1, config.p2 = 1e-3;
  config.supersampling = 2;  // 4.8 M sub-samples
  const SE3 T_body_camera(SO3::Exp(Eigen::Vector3d(-0.4, 0.2, 1.0)), Eigen::Vector3d(0.1, 0.2, 0.3));
  const CameraRenderer renderer = MakeRenderer(config, *caster, spline, T_body_camera);
  const PinholeRadtan model = CameraModelOf(config);
  const Stamp t = spline.begin() + kSecond;
  const SE3 T_world_camera = spline.Evaluate(t).T_world_body * T_body_camera;
  double worst = 0.0;
  for (int row : {0, 333, 999}) {
    auto rays = renderer.RowRays(t, row);
    ASSERT_TRUE(rays.ok());
    ASSERT_EQ(rays->size(), 4u * 1200u);
    for (int sy = 0; sy < 2; ++sy) {
      for (int u = 0; u < 1200; u += 7) {
        for (int sx = 0; sx < 2; ++sx) {
          const Ray& ray = (*rays)[static_cast<std::size_t>((sy * 1200 + u) * 2 + sx)];
          const Eigen::Vector2d pixel(u - 0.25 + 0.5 * sx, row - 0.25 + 0.5 * sy);
          const Eigen::Vector3d expected = T_world_camera.rotation() * model.Unproject(pixel);
          worst = std::max(worst, (ray.direction.cast<double>() - expected).norm());
          EXPECT_LT((ray.origin.cast<double>() - T_world_camera.translation()).norm(), 1e-5);
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(CameraRenderer, RenderFailsOutsideTheTrajectory) {
  const Scene scene = test::BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  const TrajectorySpline spline = StaticTrajectory();
  const CameraRenderer renderer = MakeRenderer(CameraConfig{}, *caster, spline, LookAlongX());
  auto frame = renderer.Render(spline.end() + 1);
  ASSERT_FALSE(frame.ok());
  EXPECT_NE(frame.error().find("outside the trajectory"), std::string::npos) << frame.error();
  EXPECT_FALSE(renderer.RowRays(spline.begin() - 1, 0).ok());
}

// ---- Image content: rendered checkerboard corners where the camera model projects them ----

// A checkerboard on the wall x = distance (facing the origin): squares of `square` m alternating between
// two materials, corners (y, z) = (y0 + i square, z0 + j square) for i in [0, columns], j in [0, rows].
struct Checkerboard {
  double distance = 3.0, square = 0.25, y0 = -1.0, z0 = -0.75;
  int columns = 8, rows = 6;
  Material a = Material::kRoadMarking, b = Material::kAsphalt;

  Eigen::Vector3d Corner(int i, int j) const { return {distance, y0 + i * square, z0 + j * square}; }

  Scene Build() const {
    Scene scene;
    for (int i = 0; i < columns; ++i) {
      for (int j = 0; j < rows; ++j) {
        const auto y = static_cast<float>(y0 + i * square), z = static_cast<float>(z0 + j * square);
        test::AddWallX(scene.mesh, static_cast<float>(distance), y, y + static_cast<float>(square), z,
                       z + static_cast<float>(square), (i + j) % 2 == 0 ? a : b);
      }
    }
    return scene;
  }
};

// Sub-pixel corners found by OpenCV (cv::cornerSubPix on the linear grey image) started 0.6 px away from
// the projection of each interior corner; returns the largest distance between found and projected corner.
double WorstCornerError(const Image& image, const Checkerboard& board, const CameraModel& projection,
                        const SE3& T_world_camera, int* found = nullptr) {
  const cv::Mat gray = LinearGray(image);
  std::vector<cv::Point2f> corners;
  std::vector<Eigen::Vector2d> truth;
  for (int i = 1; i < board.columns; ++i) {
    for (int j = 1; j < board.rows; ++j) {
      const auto pixel = projection.Project(T_world_camera.inverse() * board.Corner(i, j));
      if (!pixel || pixel->x() < 8 || pixel->y() < 8 || pixel->x() > image.width - 9 ||
          pixel->y() > image.height - 9) {
        continue;
      }
      truth.push_back(*pixel);
      corners.emplace_back(static_cast<float>(pixel->x() + 0.6), static_cast<float>(pixel->y() - 0.4));
    }
  }
  cv::cornerSubPix(gray, corners, cv::Size(7, 7), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  double worst = 0.0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    worst = std::max(worst, (Eigen::Vector2d(corners[k].x, corners[k].y) - truth[k]).norm());
  }
  if (found) *found = static_cast<int>(corners.size());
  return worst;
}

TEST(CameraRenderer, CheckerboardCornersAreWhereTheModelProjectsThem) {
  const Checkerboard board;
  const Scene scene = board.Build();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  // Slightly rotated and offset so that the board is seen in perspective, not fronto-parallel.
  const SE3 T_world_body(SO3::Exp(Eigen::Vector3d(0.4, -0.08, 0.12)), Eigen::Vector3d(0.1, 0.2, -0.1));
  const TrajectorySpline spline = StaticTrajectory(T_world_body);
  for (const bool distorted : {false, true}) {
    CameraConfig config;
    config.pinhole = {.width = 320, .height = 240, .fx = 300, .fy = 290, .cx = 158.7, .cy = 121.4};
    config.supersampling = 4;
    config.noise_std_dn = 0.0;
    config.textured = false;  // plain colours: a texture's own edges would pull the corners
    if (distorted) config.k1 = -0.2, config.k2 = 0.05, config.p1 = 8e-4, config.p2 = -6e-4;
    const CameraRenderer renderer = MakeRenderer(config, *caster, spline, LookAlongX());
    const Image image = RenderImage(renderer, kSecond);
    const SE3 T_world_camera = T_world_body * LookAlongX();
    int found = 0;
    const double worst = WorstCornerError(image, board, CameraModelOf(config), T_world_camera, &found);
    EXPECT_GE(found, 25);
    EXPECT_LT(worst, 0.1) << "distorted " << distorted;

    // A real check: the same image against a model with fx 1% off misses by more than the tolerance.
    CameraConfig wrong = config;
    wrong.pinhole.fx *= 1.01;
    EXPECT_GT(WorstCornerError(image, board, CameraModelOf(wrong), T_world_camera), 0.3);
  }
}

// ---- Shading: Lambert under the sun on the scene's surface colour, sky for misses ----

// The standard sRGB encoding of a linear value, in 8-bit DN (not rounded).
double LinearToSrgbDnReference(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return 255.0 * (x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
}

TEST(CameraRenderer, HitsAreLambertShadedSurfaceColoursAndMissesSeeTheSky) {
  Scene scene;  // a floor below the camera and a box whose faces turn different ways to the sun
  test::AddBox(scene.mesh, {-50, -50, -3}, {50, 50, -2}, Material::kConcrete);
  test::AddBox(scene.mesh, {6, -2, -2}, {8, 1, 1}, Material::kPlaster);
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  // Yawed so that two faces of the box are visible.
  const SE3 T_world_body(SO3::Exp(Eigen::Vector3d(0, 0, 0.35)), Eigen::Vector3d(0, -4, 0));
  const TrajectorySpline spline = StaticTrajectory(T_world_body);
  CameraConfig config;
  config.pinhole = {.width = 200, .height = 150, .fx = 120, .fy = 120, .cx = 99.5, .cy = 74.5};
  config.noise_std_dn = 0.0;
  config.sun_direction_world = Eigen::Vector3d(1.0, -2.0, 2.0);  // not unit: the renderer normalises it
  config.ambient = 0.3;
  const CameraRenderer renderer = MakeRenderer(config, *caster, spline, LookAlongX());
  const Image image = RenderImage(renderer, 2 * kSecond);
  const Eigen::Vector3f sun = config.sun_direction_world.normalized().cast<float>();
  int hits = 0, misses = 0, lit_faces = 0;
  double worst = 0.0;
  for (int row = 0; row < config.pinhole.height; row += 3) {
    auto rays = renderer.RowRays(2 * kSecond, row);
    ASSERT_TRUE(rays.ok());
    for (int u = 0; u < config.pinhole.width; u += 3) {
      const Ray& ray = (*rays)[static_cast<std::size_t>(u)];
      const RayHit hit = caster->Cast(ray);
      const std::uint8_t* pixel =
          &image.pixels[3 * (static_cast<std::size_t>(row) * config.pinhole.width + u)];
      if (!hit.hit()) {
        ++misses;
        EXPECT_GT(pixel[2], pixel[0]);  // blue sky
        continue;
      }
      ++hits;
      const Eigen::Vector3d X =
          ray.origin.cast<double>() + double(hit.distance) * ray.direction.cast<double>();
      const float cosine = std::max(0.0f, hit.normal.dot(sun));
      if (cosine > 0.1f) ++lit_faces;
      const Eigen::Vector3f colour = SurfaceColor(hit.material, X, hit.normal) * (0.3f + 0.7f * cosine);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(pixel[c] - LinearToSrgbDnReference(colour[c])));
    }
  }
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 500);
  EXPECT_GT(lit_faces, 200);
  EXPECT_LE(worst, 0.6);  // rounding (0.5 DN) and float/table error
  // The sky is brighter at the horizon than high up (top row of the image looks ~30 degrees up).
  const auto brightness = [&](int row, int u) {
    const std::uint8_t* p = &image.pixels[3 * (static_cast<std::size_t>(row) * config.pinhole.width + u)];
    return p[0] + p[1] + p[2];
  };
  EXPECT_GT(brightness(70, 5), brightness(0, 5));
}

}  // namespace
}  // namespace uf::sim
