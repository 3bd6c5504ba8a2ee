// `ultrafusion render` as a user runs it: EXR views against the CPU reference renderer, distorted cameras
// against the camera model's projection, .ply and .glb inputs, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "export/exr_view.h"
#include "export/splat_gltf.h"
#include "export/splat_ply.h"
#include "odometry/types/camera_model.h"
#include "splat/cpu_reference/reference_renderer.h"
#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;

// A few Gaussians 2-6 m in front of a camera at the origin looking along +z, SH degree 1.
splat::GaussianModel SmallScene() {
  splat::GaussianModel model;
  model.sh_degree = 1;
  const float sh_rest[9] = {0.1f, -0.2f, 0.05f, 0.3f, 0.0f, -0.1f, 0.0f, 0.2f, 0.1f};
  for (int i = 0; i < 12; ++i) {
    float sh[12] = {0.8f * std::sin(i * 1.f), 0.8f * std::cos(i * 0.7f), 0.3f, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 9; ++k) sh[3 + k] = sh_rest[k] * (i % 3 - 1);
    model.Add(Eigen::Vector3f(0.4f * (i % 4) - 0.6f, 0.3f * (i / 4) - 0.3f, 2.0f + 0.35f * i),
              Eigen::Vector3f(std::log(0.08f + 0.01f * i), std::log(0.05f), std::log(0.1f)),
              Eigen::Quaternionf(Eigen::AngleAxisf(0.3f * i, Eigen::Vector3f(1, 2, 3).normalized())),
              0.5f + 0.2f * i, sh);
  }
  return model;
}

constexpr const char* kCamera =
    "distortion_model: radial-tangential\nintrinsics: [60, 60, 31.5, 23.5]\ndistortion_coefficients: [0, 0, "
    "0, "
    "0]\nresolution: [64, 48]\n";
// Two poses (TUM: t x y z qx qy qz qw): the origin, and 0.2 m to the right turned 5 degrees.
constexpr const char* kPoses =
    "1.000000000 0 0 0 0 0 0 1\n"
    "1.500000000 0.2 0 0 0 0.0436194 0 0.9990482\n";

SE3 SecondPose() {
  return SE3(SO3(Eigen::Quaterniond(0.9990482, 0, 0.0436194, 0)), Eigen::Vector3d(0.2, 0, 0));
}

TEST(CliRender, ExrViewsMatchTheCpuReference) {
  testing::TempDir dir;
  ASSERT_TRUE(exporting::WriteSplatPly(SmallScene(), dir.File("scene.ply")).ok());
  const auto result = Ultrafusion(
      "render " + dir.File("scene.ply") + " --poses " + dir.Write("poses.tum", kPoses) + " --camera " +
      dir.Write("camera.yaml", kCamera) + " --out " + dir.File("views") + " --float --png");
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("render: 2 views of 64 x 48 px, 12 Gaussians"), std::string::npos)
      << result.output;
  ASSERT_TRUE(fs::exists(dir.File("views/1500000000.png")));
  Expected<exporting::ExrImage> exr = exporting::ReadExr(dir.File("views/1500000000.exr"));
  ASSERT_TRUE(exr.ok()) << exr.error();
  for (const char* channel : {"R", "G", "B", "A", "Z", exporting::kExrExpectedDepthChannel})
    ASSERT_EQ(exr->channels.count(channel), 1u) << channel;

  splat::SplatCamera camera;
  camera.pinhole = {.width = 64, .height = 48, .fx = 60, .fy = 60, .cx = 31.5, .cy = 23.5};
  camera.T_world_camera = SecondPose();
  const splat::RenderedView reference = splat::RenderReference(SmallScene(), camera, splat::RenderSettings{});
  // Float EXR of the same blend done in a different order on the device: rounding differences are ~1e-6;
  // 1e-4 leaves room for the linearization (EOTF) and still fails on any misplaced Gaussian.
  double worst_colour = 0, worst_alpha = 0;
  int covered = 0;
  for (std::size_t i = 0; i < reference.alpha.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      worst_colour =
          std::max<double>(worst_colour, std::abs(exr->channels.at(c == 0   ? "R"
                                                                   : c == 1 ? "G"
                                                                            : "B")[i] -
                                                  exporting::SrgbToLinear(reference.rgb[3 * i + c])));
    worst_alpha = std::max<double>(worst_alpha, std::abs(exr->channels.at("A")[i] - reference.alpha[i]));
    if (reference.alpha[i] > 0.5f) {
      ++covered;
      EXPECT_NEAR(exr->channels.at("Z")[i], reference.depth[i], 1e-4);
    }
  }
  EXPECT_LT(worst_colour, 1e-4);
  EXPECT_LT(worst_alpha, 1e-4);
  EXPECT_GT(covered, 50);  // the scene is in view
}

TEST(CliRender, GlbInputRendersLikeThePly) {
  testing::TempDir dir;
  ASSERT_TRUE(exporting::WriteSplatPly(SmallScene(), dir.File("scene.ply")).ok());
  ASSERT_TRUE(exporting::WriteSplatGlb(SmallScene(), dir.File("scene.glb")).ok());
  const std::string common = " --poses " + dir.Write("poses.tum", kPoses) + " --camera " +
                             dir.Write("camera.yaml", kCamera) + " --float";
  ASSERT_EQ(Ultrafusion("render " + dir.File("scene.ply") + common + " --out " + dir.File("ply")).code, 0);
  const auto glb = Ultrafusion("render " + dir.File("scene.glb") + common + " --out " + dir.File("glb"));
  ASSERT_EQ(glb.code, 0) << glb.output;
  Expected<exporting::ExrImage> a = exporting::ReadExr(dir.File("ply/1000000000.exr"));
  Expected<exporting::ExrImage> b = exporting::ReadExr(dir.File("glb/1000000000.exr"));
  ASSERT_TRUE(a.ok() && b.ok());
  // The glb stores linear scales, opacities and rotations: conversions cost a few ulps, no more.
  for (std::size_t i = 0; i < a->channels.at("A").size(); ++i)
    EXPECT_NEAR(a->channels.at("A")[i], b->channels.at("A")[i], 1e-4);
}

TEST(CliRender, DistortedCameraPutsAGaussianWhereTheModelProjectsIt) {
  testing::TempDir dir;
  splat::GaussianModel model;
  const Eigen::Vector3f point(-1.8f, -1.2f, 3.0f);  // towards the top-left corner, where distortion is large
  model.AddConstantColor(point, Eigen::Vector3f::Constant(std::log(0.01f)), Eigen::Quaternionf::Identity(),
                         6.0f, Eigen::Vector3f(1, 1, 1));
  ASSERT_TRUE(exporting::WriteSplatPly(model, dir.File("dot.ply")).ok());
  const std::string camera =
      "distortion_model: radial-tangential\nintrinsics: [100, 100, 79.5, 59.5]\ndistortion_coefficients: "
      "[-0.3, "
      "0.08, 0, 0]\nresolution: [160, 120]\n";
  const auto result = Ultrafusion(
      "render " + dir.File("dot.ply") + " --poses " + dir.Write("pose.tum", "2 0 0 0 0 0 0 1\n") +
      " --camera " + dir.Write("camera.yaml", camera) + " --out " + dir.File("views") + " --float");
  ASSERT_EQ(result.code, 0) << result.output;
  Expected<exporting::ExrImage> exr = exporting::ReadExr(dir.File("views/2000000000.exr"));
  ASSERT_TRUE(exr.ok()) << exr.error();
  // Alpha-weighted centroid of the dot against the distortion model's projection of its centre.
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 160, .height = 120, .fx = 100, .fy = 100, .cx = 79.5, .cy = 59.5};
  k.k1 = -0.3, k.k2 = 0.08;
  const Eigen::Vector2d expected = *PinholeRadtan(k).Project(point.cast<double>());
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double mass = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const double a = exr->channels.at("A")[y * 160 + x];
      centroid += a * Eigen::Vector2d(x, y);
      mass += a;
    }
  ASSERT_GT(mass, 1.0);
  // Without the resampling the dot would sit at the pinhole projection, several pixels away.
  const Eigen::Vector2d pinhole(100 * point.x() / point.z() + 79.5, 100 * point.y() / point.z() + 59.5);
  ASSERT_GT((pinhole - expected).norm(), 5.0);
  EXPECT_LT((centroid / mass - expected).norm(), 0.5)
      << (centroid / mass).transpose() << " vs " << expected.transpose();
}

TEST(CliRender, BadInputGivesClearErrors) {
  testing::TempDir dir;
  ASSERT_TRUE(exporting::WriteSplatPly(SmallScene(), dir.File("scene.ply")).ok());
  const std::string poses = dir.Write("poses.tum", kPoses), camera = dir.Write("camera.yaml", kCamera);
  // Impossible intrinsics: a usage error naming the file and key.
  const std::string bad_camera = dir.Write(
      "bad.yaml",
      "distortion_model: radial-tangential\nintrinsics: [0, 60, 31.5, 23.5]\ndistortion_coefficients: [0, "
      "0, 0, 0]\nresolution: [64, 48]\n");
  auto result = Ultrafusion("render " + dir.File("scene.ply") + " --poses " + poses + " --camera " +
                            bad_camera + " --out " + dir.File("a"));
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("bad.yaml: camera intrinsics: fx = 0"), std::string::npos) << result.output;
  // Not a splat file.
  result = Ultrafusion("render " + poses + " --poses " + poses + " --camera " + camera + " --out " +
                       dir.File("b"));
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("unknown splat file type '.tum'"), std::string::npos) << result.output;
  // A damaged PLY: truncated after the header.
  const std::string ply = dir.File("scene.ply");
  fs::resize_file(ply, fs::file_size(ply) / 2);
  result =
      Ultrafusion("render " + ply + " --poses " + poses + " --camera " + camera + " --out " + dir.File("c"));
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("scene.ply"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir.File("c")));
  // No Vulkan driver at all: says what to install.
  ASSERT_TRUE(exporting::WriteSplatPly(SmallScene(), dir.File("ok.ply")).ok());
  result = Ultrafusion("render " + dir.File("ok.ply") + " --poses " + poses + " --camera " + camera +
                       " --out " + dir.File("d") + " --device no-such-gpu");
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("no-such-gpu"), std::string::npos) << result.output;
  result = test::Ultrafusion("render " + dir.File("ok.ply") + " --poses " + poses + " --camera " + camera +
                                 " --out " + dir.File("e"),
                             true, "VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json");
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("mesa-vulkan-drivers"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace uf
