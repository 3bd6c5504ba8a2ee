// KHR_gaussian_splatting .glb: the Khronos validator's verdict (only the extension it may not know is
// allowed to be reported), and damaged or unsupported files, each rejected with a message naming the field.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "export/splat_gltf.h"
#include "export_test_util.h"
#include "gltf_test_util.h"
#include "splat_test_util.h"

namespace uf::exporting {
namespace {

const std::string kPrefix = "KHR_gaussian_splatting:";

TEST(SplatGltfValidator, OnlyTheUnknownExtensionIsReported) {
  if (const std::string why = test::ValidatorUnavailable(); !why.empty()) GTEST_SKIP() << why;
  test::ScratchDir dir;
  const std::filesystem::path glb = dir / "splats.glb";
  ASSERT_TRUE(WriteSplatGlb(test::RandomModel(3, 200, 9), glb.string()).ok());
  std::string log;
  const int status = test::Validate(glb, log);
  ASSERT_TRUE(status >= 0 && status != 2) << log;
  // Messages look like "  [severity] CODE /pointer: text"; severity 0 errors, 1 warnings. A validator that
  // predates the extension flags its attribute names (error) and the extension itself (info).
  std::istringstream lines(log);
  std::string message;
  int checked = 0;
  while (std::getline(lines, message)) {
    if (message.rfind("  [0]", 0) != 0 && message.rfind("  [1]", 0) != 0) continue;
    ++checked;
    EXPECT_NE(message.find("MESH_PRIMITIVE_INVALID_ATTRIBUTE /meshes/0/primitives/0/attributes/" + kPrefix),
              std::string::npos)
        << message;
  }
  EXPECT_LE(checked, 4 + 15 + 1) << log;  // at most the 5 + 15 attribute names of the extension
}

// Writes a valid file, lets `damage` change it through tinygltf, and expects ReadSplatGltf to fail with a
// message containing `part`.
void ExpectError(const std::function<void(tinygltf::Model&)>& damage, const std::string& part) {
  test::ScratchDir dir;
  ASSERT_TRUE(WriteSplatGlb(test::RandomModel(1, 5, 4), (dir / "good.glb").string()).ok());
  tinygltf::Model m = test::LoadGlb(dir / "good.glb");
  damage(m);
  tinygltf::TinyGLTF gltf;
  const std::string path = (dir / "bad.glb").string();
  ASSERT_TRUE(gltf.WriteGltfSceneToFile(&m, path, false, true, false, true));
  Expected<splat::GaussianModel> read = ReadSplatGltf(path);
  ASSERT_FALSE(read.ok()) << "accepted, expected: " << part;
  EXPECT_NE(read.error().find("bad.glb"), std::string::npos) << read.error();
  EXPECT_NE(read.error().find(part), std::string::npos) << read.error();
}

tinygltf::Primitive& Prim(tinygltf::Model& m) { return m.meshes[0].primitives[0]; }

// Element `i` of the float accessor of `attribute`, for overwriting.
float* Floats(tinygltf::Model& m, const std::string& attribute, std::size_t i) {
  const tinygltf::Accessor& a = m.accessors[Prim(m).attributes.at(attribute)];
  const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
  const int n = tinygltf::GetNumComponentsInType(a.type);
  return reinterpret_cast<float*>(m.buffers[0].data.data() + v.byteOffset + a.byteOffset) + n * i;
}

TEST(SplatGltfErrors, MissingOrPartialAttributes) {
  ExpectError([](tinygltf::Model& m) { Prim(m).attributes.erase(kPrefix + "SCALE"); },
              "'" + kPrefix + "SCALE' is missing");
  ExpectError([](tinygltf::Model& m) { Prim(m).attributes.erase(kPrefix + "SH_DEGREE_0_COEF_0"); },
              "SH_DEGREE_0_COEF_0' is missing");
  ExpectError([](tinygltf::Model& m) { Prim(m).attributes.erase(kPrefix + "SH_DEGREE_1_COEF_1"); },
              "degree 1 is partially defined");
  ExpectError(
      [](tinygltf::Model& m) {  // degree 2 coefficients without degree 1
        for (int n = 0; n < 3; ++n)
          Prim(m).attributes.erase(kPrefix + "SH_DEGREE_1_COEF_" + std::to_string(n));
        for (int n = 0; n < 5; ++n)
          Prim(m).attributes[kPrefix + "SH_DEGREE_2_COEF_" + std::to_string(n)] =
              Prim(m).attributes["POSITION"];
      },
      "degree 2");
}

TEST(SplatGltfErrors, UnsupportedVariants) {
  ExpectError(
      [](tinygltf::Model& m) {
        Prim(m).extensions["KHR_gaussian_splatting"].Get<tinygltf::Value::Object>()["colorSpace"] =
            tinygltf::Value(std::string("lin_rec709_display"));
      },
      "colorSpace 'lin_rec709_display'");
  ExpectError(
      [](tinygltf::Model& m) {
        Prim(m).extensions["KHR_gaussian_splatting"].Get<tinygltf::Value::Object>()["kernel"] =
            tinygltf::Value(std::string("customShape"));
      },
      "kernel 'customShape'");
  ExpectError(
      [](tinygltf::Model& m) {
        m.extensionsUsed.push_back("KHR_gaussian_splatting_compression_spz_2");
        m.extensionsRequired.push_back("KHR_gaussian_splatting_compression_spz_2");
      },
      "requires the glTF extension 'KHR_gaussian_splatting_compression_spz_2'");
  ExpectError([](tinygltf::Model& m) { Prim(m).mode = TINYGLTF_MODE_TRIANGLES; }, "mode must be POINTS");
  ExpectError([](tinygltf::Model& m) { Prim(m).extensions.clear(); }, "no mesh primitive with the KHR");
}

TEST(SplatGltfErrors, BadValuesAndAccessors) {
  ExpectError([](tinygltf::Model& m) { *Floats(m, kPrefix + "OPACITY", 3) = 1.5f; },
              "Gaussian 3: opacity must be in [0, 1], got 1.5");
  ExpectError([](tinygltf::Model& m) { Floats(m, kPrefix + "SCALE", 2)[1] = -0.1f; },
              "Gaussian 2: scale_1 must be positive");
  ExpectError([](tinygltf::Model& m) { Floats(m, "POSITION", 0)[0] = std::nanf(""); },
              "Gaussian 0: position");
  ExpectError(
      [](tinygltf::Model& m) { m.accessors[Prim(m).attributes.at(kPrefix + "SCALE")].count = 1u << 30; },
      "does not fit");
  ExpectError([](tinygltf::Model& m) { m.accessors[Prim(m).attributes.at(kPrefix + "OPACITY")].count = 4; },
              "different counts");
  ExpectError([](tinygltf::Model& m) { m.nodes[0].scale = {1, -1, 1}; }, "uniform positive scale");
}

TEST(SplatGltfErrors, GarbageFiles) {
  test::ScratchDir dir;
  std::ofstream(dir / "g.glb", std::ios::binary) << "glTF\x02\0\0\0 garbage";
  Expected<splat::GaussianModel> garbage = ReadSplatGltf((dir / "g.glb").string());
  ASSERT_FALSE(garbage.ok());
  EXPECT_NE(garbage.error().find("not a readable glTF"), std::string::npos) << garbage.error();
  std::ofstream(dir / "t.gltf") << "{ this is not json";
  EXPECT_FALSE(ReadSplatGltf((dir / "t.gltf").string()).ok());
  EXPECT_FALSE(ReadSplatGltf((dir / "missing.glb").string()).ok());
  splat::GaussianModel empty;
  EXPECT_FALSE(WriteSplatGlb(empty, (dir / "e.glb").string()).ok());
}

}  // namespace
}  // namespace uf::exporting
