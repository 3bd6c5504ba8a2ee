// KHR_gaussian_splatting .glb: round trips of every SH degree (tolerances from the float conversions only),
// the written file checked against the specification with tinygltf, node transforms applied on reading.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include "export/sh_rotation.h"
#include "export/splat_gltf.h"
#include "export_test_util.h"
#include "gltf_test_util.h"
#include "splat_test_util.h"

namespace uf::exporting {
namespace {

const std::string kExt = "KHR_gaussian_splatting";

using test::LoadGlb;

template <int N>
Eigen::Matrix<float, N, 1> Element(const tinygltf::Model& m, int accessor, std::size_t i) {
  const tinygltf::Accessor& a = m.accessors.at(accessor);
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& v = m.bufferViews.at(a.bufferView);
  Eigen::Matrix<float, N, 1> out;
  std::memcpy(out.data(), m.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset + i * 4 * N, 4 * N);
  return out;
}

double Sigmoid(double x) { return 1 / (1 + std::exp(-x)); }

// Bound of the float rounding of a stored value re-read into a float: half an ulp, 2^-24 relative.
double FloatRounding(double x) { return 6e-8 * std::abs(x); }

TEST(SplatGltf, RoundTripOfEveryShDegreeWithinFloatRounding) {
  test::ScratchDir dir;
  for (int degree = 0; degree <= 3; ++degree) {
    const splat::GaussianModel model = test::RandomModel(degree, 300, 20 + degree);
    const std::string path = (dir / ("splats_" + std::to_string(degree) + ".glb")).string();
    ASSERT_TRUE(WriteSplatGlb(model, path).ok());
    Expected<splat::GaussianModel> back = ReadSplatGltf(path);
    ASSERT_TRUE(back.ok()) << back.error();
    ASSERT_EQ(back->sh_degree, degree);
    ASSERT_EQ(back->size(), model.size());
    for (std::size_t i = 0; i < model.size(); ++i) {
      EXPECT_EQ(back->positions[i], model.positions[i]) << i;  // the axis change is a signed permutation
      // exp -> float -> log: the stored sigma's rounding (2^-24 relative) becomes 2^-24 absolute in the log.
      for (int a = 0; a < 3; ++a) {
        const double x = model.log_scales[i][a];
        EXPECT_NEAR(back->log_scales[i][a], x, 6e-8 + 2 * FloatRounding(x)) << i;
      }
      // sigmoid -> float -> logit: dlogit = dp / (p (1 - p)) with dp <= 2^-24 p.
      const double x = model.opacity_logits[i], p = Sigmoid(x);
      EXPECT_NEAR(back->opacity_logits[i], x, 1.1 * 6e-8 / (1 - p) + 2 * FloatRounding(x)) << i;
      // Written normalized; the rotation by q_R and back costs a few float roundings.
      const Eigen::Vector4f q = model.rotations[i].normalized().coeffs(), r = back->rotations[i].coeffs();
      EXPECT_LT((q - (q.dot(r) < 0 ? -r : r)).norm(), 1e-6) << i;
      // SH: D_l is orthogonal, so the rounding of the stored rotated coefficients (2^-24 of their norm)
      // carries back unamplified; plus the final rounding.
      const int stride = model.ShStride();
      for (int k = 0; k < stride; ++k) {
        const int l = static_cast<int>(std::sqrt(double(k / 3))), c = k % 3;
        double norm = 0;
        for (int j = l * l; j < (l + 1) * (l + 1); ++j) norm += std::pow(model.sh[i * stride + 3 * j + c], 2);
        const double expected = model.sh[i * stride + k];
        EXPECT_NEAR(back->sh[i * stride + k], expected,
                    2 * FloatRounding(std::sqrt(norm)) + 2 * FloatRounding(expected))
            << i << " " << k;
      }
    }
  }
  EXPECT_EQ(dir.Entries().size(), 4u);
}

// One known Gaussian, read with tinygltf and compared with what the specification prescribes.
TEST(SplatGltf, FileFollowsTheSpecification) {
  test::ScratchDir dir;
  splat::GaussianModel model;
  model.sh_degree = 1;
  std::vector<float> sh(12, 0.0f);
  sh[3] = 0.3f, sh[6] = -0.7f, sh[9] = 1.1f;  // channel R of degree 1: (a, b, c)
  model.Add({1, 2, 3}, {0, std::log(2.0f), -1}, Eigen::Quaternionf::Identity(), 0.0f, sh.data());
  ASSERT_TRUE(WriteSplatGlb(model, (dir / "one.glb").string()).ok());
  const tinygltf::Model m = LoadGlb(dir / "one.glb");
  EXPECT_EQ(m.extensionsUsed, std::vector<std::string>{kExt});
  EXPECT_TRUE(m.extensionsRequired.empty());
  ASSERT_EQ(m.meshes.size(), 1u);
  const tinygltf::Primitive& prim = m.meshes[0].primitives.at(0);
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_POINTS);
  const tinygltf::Value& ext = prim.extensions.at(kExt);
  EXPECT_EQ(ext.Get("kernel").Get<std::string>(), "ellipse");
  EXPECT_EQ(ext.Get("colorSpace").Get<std::string>(), "srgb_rec709_display");
  std::vector<std::string> names;
  for (const auto& [name, accessor] : prim.attributes) names.push_back(name);
  const std::string p = "KHR_gaussian_splatting:";
  EXPECT_EQ(names,
            (std::vector<std::string>{"COLOR_0", p + "OPACITY", p + "ROTATION", p + "SCALE",
                                      p + "SH_DEGREE_0_COEF_0", p + "SH_DEGREE_1_COEF_0",
                                      p + "SH_DEGREE_1_COEF_1", p + "SH_DEGREE_1_COEF_2", "POSITION"}));
  auto at = [&](const std::string& name) { return prim.attributes.at(name); };
  EXPECT_EQ(m.accessors[at(p + "ROTATION")].type, TINYGLTF_TYPE_VEC4);
  EXPECT_EQ(m.accessors[at(p + "OPACITY")].type, TINYGLTF_TYPE_SCALAR);
  // y-up: (x, y, z) -> (x, z, -y).
  EXPECT_EQ(Element<3>(m, at("POSITION"), 0), Eigen::Vector3f(1, 3, -2));
  EXPECT_EQ(m.accessors[at("POSITION")].minValues, (std::vector<double>{1, 3, -2}));
  // Identity in our frame is the axis rotation itself, -90 deg about x, written x y z w.
  EXPECT_TRUE(Element<4>(m, at(p + "ROTATION"), 0)
                  .isApprox(Eigen::Vector4f(-std::sqrt(0.5f), 0, 0, std::sqrt(0.5f)), 1e-6f));
  EXPECT_TRUE(
      Element<3>(m, at(p + "SCALE"), 0).isApprox(Eigen::Vector3f(1, 2, std::exp(-1.0f)), 1e-6f));  // linear
  EXPECT_EQ(Element<1>(m, at(p + "OPACITY"), 0)[0], 0.5f);  // sigmoid(0), linear
  // Degree 1 (a, b, c) -> (-b, a, c) (hand-derived in test_sh_rotation.cpp).
  EXPECT_NEAR(Element<3>(m, at(p + "SH_DEGREE_1_COEF_0"), 0)[0], 0.7f, 1e-6);
  EXPECT_NEAR(Element<3>(m, at(p + "SH_DEGREE_1_COEF_1"), 0)[0], 0.3f, 1e-6);
  EXPECT_NEAR(Element<3>(m, at(p + "SH_DEGREE_1_COEF_2"), 0)[0], 1.1f, 1e-6);
  // COLOR_0: DC colour 0.5 (sRGB) decoded to linear, alpha = opacity.
  EXPECT_TRUE(Element<4>(m, at("COLOR_0"), 0)
                  .isApprox(Eigen::Vector4f(0.21404114f, 0.21404114f, 0.21404114f, 0.5f), 1e-6f));
}

// A node with translation t, rotation Rn and uniform scale 2: positions, scales, rotations and the colour
// seen from a direction move with the node, then come to our z-up frame.
TEST(SplatGltf, ReadingAppliesNodeTransforms) {
  test::ScratchDir dir;
  const splat::GaussianModel model = test::RandomModel(2, 20, 3);
  ASSERT_TRUE(WriteSplatGlb(model, (dir / "a.glb").string()).ok());
  tinygltf::Model m = LoadGlb(dir / "a.glb");
  const Eigen::Quaterniond qn(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()));
  m.nodes[0].translation = {1, 2, 3};
  m.nodes[0].rotation = {qn.x(), qn.y(), qn.z(), qn.w()};
  m.nodes[0].scale = {2, 2, 2};
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&m, (dir / "b.glb").string(), false, true, false, true));
  Expected<splat::GaussianModel> back = ReadSplatGltf((dir / "b.glb").string());
  ASSERT_TRUE(back.ok()) << back.error();
  Eigen::Matrix3d R;  // ours -> glTF
  R << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  const Eigen::Matrix3d Rn = qn.toRotationMatrix(), moved = R.transpose() * Rn * R;  // in our frame
  const Eigen::Vector3d t = R.transpose() * Eigen::Vector3d(1, 2, 3);
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Eigen::Vector3d p = model.positions[i].cast<double>();
    EXPECT_TRUE(back->positions[i].cast<double>().isApprox(t + 2 * moved * p, 1e-6)) << i;
    EXPECT_TRUE(
        back->log_scales[i].isApprox(model.log_scales[i] + Eigen::Vector3f::Constant(std::log(2.0f)), 1e-5f));
    const Eigen::Matrix3d expected =
        moved * model.rotations[i].cast<double>().normalized().toRotationMatrix();
    EXPECT_TRUE(back->rotations[i].cast<double>().normalized().toRotationMatrix().isApprox(expected, 1e-5))
        << i;
    const Eigen::Vector3d d = Eigen::Vector3d(0.3, -0.4, 0.8).normalized();
    const std::array<double, 16> before = ShBasis(d), after = ShBasis(moved * d);
    for (int c = 0; c < 3; ++c) {
      double seen = 0, seen_moved = 0;
      for (int k = 0; k < 9; ++k) {
        seen += model.sh[i * 27 + 3 * k + c] * before[k];
        seen_moved += back->sh[i * 27 + 3 * k + c] * after[k];
      }
      EXPECT_NEAR(seen_moved, seen, 1e-5) << i;
    }
  }
  m.nodes[0].scale = {1, 2, 1};
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&m, (dir / "c.glb").string(), false, true, false, true));
  Expected<splat::GaussianModel> stretched = ReadSplatGltf((dir / "c.glb").string());
  ASSERT_FALSE(stretched.ok());
  EXPECT_NE(stretched.error().find("uniform positive scale"), std::string::npos) << stretched.error();
}

}  // namespace
}  // namespace uf::exporting
