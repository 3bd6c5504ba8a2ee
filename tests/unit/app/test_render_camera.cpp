// The camera file of `ultrafusion render` (the calibration files' intrinsics dialect): parsing, resizing, and
// errors that name file, key, line and value.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "viewer/app/config/render_camera.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;

std::string WriteCameraFile(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("uf_render_camera_" + name + ".yaml");
  std::ofstream(path) << text;
  return path.string();
}

// The calibration files' dialect (odometry/io/camera_calibration.h).
std::string Camera(const std::string& intrinsics, const std::string& coefficients,
                   const std::string& resolution) {
  return "distortion_model: radial-tangential\nintrinsics: " + intrinsics +
         "\ndistortion_coefficients: " + coefficients + "\nresolution: " + resolution + "\n";
}

const std::string kPinhole = Camera("[525, 520.5, 319.5, 239.5]", "[0, 0, 0, 0]", "[640, 480]");

TEST(RenderCamera, ReadsPinholeAndOptionalDistortion) {
  Expected<RenderCamera> camera = LoadRenderCamera(WriteCameraFile("plain", kPinhole));
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_EQ(camera->intrinsics.pinhole.width, 640);
  EXPECT_EQ(camera->intrinsics.pinhole.height, 480);
  EXPECT_DOUBLE_EQ(camera->intrinsics.pinhole.fx, 525);
  EXPECT_DOUBLE_EQ(camera->intrinsics.pinhole.fy, 520.5);
  EXPECT_DOUBLE_EQ(camera->intrinsics.pinhole.cy, 239.5);
  EXPECT_FALSE(camera->distorted);
  // A point on the optical axis lands on the principal point.
  EXPECT_TRUE(camera->model->Project(Eigen::Vector3d(0, 0, 2))->isApprox(Eigen::Vector2d(319.5, 239.5)));

  camera = LoadRenderCamera(WriteCameraFile(
      "radtan", "camera_model: pinhole\n" +
                    Camera("[525, 520.5, 319.5, 239.5]", "[-0.3, 0.1, 0.001, 0, 0.01]", "[640, 480]")));
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_TRUE(camera->distorted);
  EXPECT_DOUBLE_EQ(camera->intrinsics.k1, -0.3);
  EXPECT_DOUBLE_EQ(camera->intrinsics.p1, 0.001);
  EXPECT_DOUBLE_EQ(camera->intrinsics.k3, 0.01);
}

TEST(RenderCamera, TheRepositorysCameraFileIsTheSimulatorsCamera) {
  Expected<RenderCamera> camera =
      LoadRenderCamera(std::string(UF_SOURCE_DIR) + "/configs/render-camera.yaml");
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_EQ(camera->intrinsics.pinhole.width, 640);
  EXPECT_EQ(camera->intrinsics.pinhole.height, 480);
  EXPECT_EQ(camera->intrinsics.pinhole.fx, 400);
  EXPECT_EQ(camera->intrinsics.pinhole.cx, 319.5);
  EXPECT_FALSE(camera->distorted);
}

TEST(RenderCamera, ResizeScalesTheIntrinsicsAboutPixelCorners) {
  Expected<RenderCamera> camera = LoadRenderCamera(WriteCameraFile("resize", kPinhole));
  ASSERT_TRUE(camera.ok());
  Expected<std::shared_ptr<const CameraModel>> half = ResizeCameraModel(*camera->model, 320, 240);
  ASSERT_TRUE(half.ok()) << half.error();
  const auto* radtan = dynamic_cast<const PinholeRadtan*>(half->get());
  ASSERT_NE(radtan, nullptr);
  EXPECT_DOUBLE_EQ(radtan->intrinsics().pinhole.fx, 262.5);
  // The image centre stays the image centre: (319.5 + 0.5) / 2 - 0.5 = 159.5.
  EXPECT_DOUBLE_EQ(radtan->intrinsics().pinhole.cx, 159.5);
  EXPECT_DOUBLE_EQ(radtan->intrinsics().pinhole.cy, 119.5);
  EXPECT_EQ(radtan->width(), 320);
  // A fisheye keeps its model and coefficients.
  const Equidistant fisheye(EquidistantIntrinsics{{640, 480, 300, 300, 319.5, 239.5}, 0.1, -0.02, 0, 0});
  Expected<std::shared_ptr<const CameraModel>> small = ResizeCameraModel(fisheye, 160, 120);
  ASSERT_TRUE(small.ok()) << small.error();
  const auto* equidistant = dynamic_cast<const Equidistant*>(small->get());
  ASSERT_NE(equidistant, nullptr);
  EXPECT_DOUBLE_EQ(equidistant->intrinsics().pinhole.fx, 75);
  EXPECT_DOUBLE_EQ(equidistant->intrinsics().pinhole.cx, 79.5);
  EXPECT_DOUBLE_EQ(equidistant->intrinsics().k1, 0.1);
}

TEST(RenderCamera, ErrorsNameTheFileKeyAndValue) {
  struct Case {
    std::string name, text, expected;
  };
  const std::string ok_intrinsics = "[50, 50, 31.5, 23.5]", none = "[0, 0, 0, 0]";
  const std::vector<Case> cases = {
      {"model", "camera_model: fisheye\n" + Camera(ok_intrinsics, none, "[64, 48]"),
       "camera_model (line 1): 'fisheye' is not supported (pinhole)"},
      {"equidistant",
       "distortion_model: equidistant\nintrinsics: [50, 50, 31.5, 23.5]\ndistortion_coefficients: [0, 0, 0, "
       "0]\nresolution: [64, 48]\n",
       "distortion_model: only radial-tangential cameras are rendered"},
      {"unknown", kPinhole + "k1: 0.1\n",
       "k1 (line 5): unknown key (expected camera_model, distortion_model"},
      {"missing",
       "distortion_model: radial-tangential\nintrinsics: [50, 50, 31.5, 23.5]\nresolution: [64, 48]\n",
       "camera calibration without 'distortion_coefficients'"},
      {"negative_focal", Camera("[-50, 50, 31.5, 23.5]", none, "[64, 48]"), "fx = -50"},
      {"centre_outside", Camera("[50, 50, 31.5, 480]", none, "[64, 48]"), "cy = 480"},
      {"size", Camera(ok_intrinsics, none, "[0, 48]"), "width = 0"},
      {"huge", Camera(ok_intrinsics, none, "[20000, 48]"), "resolution: must be at most 16384"},
      {"fractional_size", Camera(ok_intrinsics, none, "[64.5, 48]"),
       "resolution (line 4): needs 2 whole numbers (width, height), found '[64.5, 48]'"},
      {"nan", Camera("[.nan, 50, 31.5, 23.5]", none, "[64, 48]"), "fx = nan"},
      {"count", Camera("[50, 50, 31.5]", none, "[64, 48]"),
       "intrinsics (line 2): needs 4 numbers (fx, fy, cx, cy), found '[50, 50, 31.5]'"},
      {"distortion", Camera(ok_intrinsics, "[0.1, 0.2]", "[64, 48]"),
       "distortion_coefficients (line 3): needs 4 or 5 numbers"},
      {"not_a_map", "- 1\n- 2\n", "expected a map"},
  };
  for (const Case& c : cases) {
    const std::string path = WriteCameraFile(c.name, c.text);
    Expected<RenderCamera> camera = LoadRenderCamera(path);
    ASSERT_FALSE(camera.ok()) << c.name;
    EXPECT_NE(camera.error().find(path), std::string::npos) << camera.error();
    EXPECT_NE(camera.error().find(c.expected), std::string::npos) << c.name << ": " << camera.error();
  }
  EXPECT_NE(LoadRenderCamera("/nonexistent/camera.yaml").error().find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace uf::app
