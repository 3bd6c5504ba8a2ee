// The camera file of `ultrafusion render`: parsing, resizing, and errors that name file, key and value.
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

const char* kPinhole = "model: pinhole\nwidth: 640\nheight: 480\nfx: 525\nfy: 520.5\ncx: 319.5\ncy: 239.5\n";

TEST(RenderCamera, ReadsPinholeAndOptionalDistortion) {
  Expected<RenderCamera> camera = LoadRenderCamera(WriteCameraFile("plain", kPinhole));
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_EQ(camera->width, 640);
  EXPECT_EQ(camera->height, 480);
  EXPECT_DOUBLE_EQ(camera->intrinsics.fy, 520.5);
  EXPECT_FALSE(camera->distorted);
  // A point on the optical axis lands on the principal point.
  EXPECT_TRUE(camera->model->Project(Eigen::Vector3d(0, 0, 2))->isApprox(Eigen::Vector2d(319.5, 239.5)));

  camera = LoadRenderCamera(
      WriteCameraFile("radtan", std::string(kPinhole) + "distortion: [-0.3, 0.1, 0.001, 0, 0.01]\n"));
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_TRUE(camera->distorted);
  EXPECT_DOUBLE_EQ(camera->intrinsics.k1, -0.3);
  EXPECT_DOUBLE_EQ(camera->intrinsics.k3, 0.01);
}

TEST(RenderCamera, ResizeScalesTheIntrinsicsAboutPixelCorners) {
  Expected<RenderCamera> camera = LoadRenderCamera(WriteCameraFile("resize", kPinhole));
  ASSERT_TRUE(camera.ok());
  const RenderCamera half = ResizeRenderCamera(*camera, 320, 240);
  EXPECT_DOUBLE_EQ(half.intrinsics.fx, 262.5);
  // The image centre stays the image centre: (319.5 + 0.5) / 2 - 0.5 = 159.5.
  EXPECT_DOUBLE_EQ(half.intrinsics.cx, 159.5);
  EXPECT_DOUBLE_EQ(half.intrinsics.cy, 119.5);
  EXPECT_EQ(half.model->width(), 320);
}

TEST(RenderCamera, ErrorsNameTheFileKeyAndValue) {
  struct Case {
    std::string name, text, expected;
  };
  const std::vector<Case> cases = {
      {"model", "model: fisheye\nwidth: 64\nheight: 48\nfx: 1\nfy: 1\ncx: 1\ncy: 1\n",
       "only 'pinhole' is supported, got 'fisheye'"},
      {"unknown", std::string(kPinhole) + "k1: 0.1\n", "k1 (line 8): unknown key"},
      {"missing", "model: pinhole\nwidth: 64\nheight: 48\nfx: 50\nfy: 50\ncx: 31.5\n", "missing key 'cy'"},
      {"negative_focal", "model: pinhole\nwidth: 64\nheight: 48\nfx: -50\nfy: 50\ncx: 31.5\ncy: 23.5\n",
       "fx"},
      {"centre_outside", "model: pinhole\nwidth: 64\nheight: 48\nfx: 50\nfy: 50\ncx: 31.5\ncy: 480\n", "cy"},
      {"size", "model: pinhole\nwidth: 0\nheight: 48\nfx: 50\nfy: 50\ncx: 0\ncy: 23.5\n",
       "width (line 2): expected a whole number"},
      {"nan", "model: pinhole\nwidth: 64\nheight: 48\nfx: .nan\nfy: 50\ncx: 31.5\ncy: 23.5\n",
       "fx (line 4): expected a finite number"},
      {"distortion", std::string(kPinhole) + "distortion: [0.1, 0.2]\n",
       "distortion (line 8): expected [k1, k2, p1, p2]"},
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
