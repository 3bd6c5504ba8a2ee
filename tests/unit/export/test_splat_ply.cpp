// 3DGS splat PLY: bit-exact round trips, the standard layout checked byte by byte with an independent
// parser, hand-written files (ASCII, shuffled, extra properties, big endian), and every kind of bad input.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "export/splat_ply.h"
#include "export_test_util.h"
#include "splat_test_util.h"

namespace uf::exporting {
namespace {

void WriteText(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

template <typename T>
bool BitEqual(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

TEST(SplatPly, RoundTripIsBitExactForEveryShDegree) {
  test::ScratchDir dir;
  for (int degree = 0; degree <= 3; ++degree) {
    const splat::GaussianModel model = test::RandomModel(degree, 257, 10 + degree);
    const std::string path = (dir / ("d" + std::to_string(degree) + ".ply")).string();
    ASSERT_TRUE(WriteSplatPly(model, path).ok());
    std::vector<std::string> ignored;
    Expected<splat::GaussianModel> back = ReadSplatPly(path, &ignored);
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_TRUE(ignored.empty());
    ASSERT_EQ(back->sh_degree, degree);
    ASSERT_EQ(back->size(), model.size());
    ASSERT_EQ(back->sh.size(), model.sh.size());
    for (std::size_t i = 0; i < model.size(); ++i) {
      EXPECT_TRUE(BitEqual(back->positions[i], model.positions[i])) << i;
      EXPECT_TRUE(BitEqual(back->log_scales[i], model.log_scales[i])) << i;
      EXPECT_TRUE(BitEqual(back->rotations[i].coeffs(), model.rotations[i].coeffs())) << i;
      EXPECT_TRUE(BitEqual(back->opacity_logits[i], model.opacity_logits[i])) << i;
    }
    EXPECT_EQ(std::memcmp(back->sh.data(), model.sh.data(), model.sh.size() * sizeof(float)), 0);
  }
  EXPECT_EQ(dir.Entries().size(), 4u);  // no temporary file left behind
}

// The file read back by hand: property names and order of the standard layout, and f_rest channel-major.
TEST(SplatPly, WritesTheStandardLayoutWithChannelMajorRest) {
  test::ScratchDir dir;
  splat::GaussianModel model;
  model.sh_degree = 2;  // 9 coefficients per channel, 24 f_rest
  std::vector<float> sh(model.ShStride());
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c) sh[k * 3 + c] = 100.0f * c + k;  // model: coefficient-major
  model.Add({1, 2, 3}, {-1, -2, -3}, Eigen::Quaternionf(0.5f, 0.25f, -0.125f, 2.0f), 1.5f, sh.data());
  const std::filesystem::path path = dir / "one.ply";
  ASSERT_TRUE(WriteSplatPly(model, path.string()).ok());

  const std::vector<std::uint8_t> bytes = test::ReadBytes(path);
  const std::string text(bytes.begin(), bytes.end());
  const std::size_t body = text.find("end_header\n") + 11;
  std::istringstream header(text.substr(0, body));
  std::string line;
  std::vector<std::string> names;
  bool binary_le = false, one_vertex = false;
  while (std::getline(header, line)) {
    if (line == "format binary_little_endian 1.0") binary_le = true;
    if (line == "element vertex 1") one_vertex = true;
    if (line.rfind("property float ", 0) == 0) names.push_back(line.substr(15));
  }
  EXPECT_TRUE(binary_le);
  EXPECT_TRUE(one_vertex);
  ASSERT_EQ(names, test::StandardPropertyNames(2));
  ASSERT_EQ(bytes.size(), body + 4 * names.size());
  auto value = [&](const std::string& name) {
    const std::size_t p = std::find(names.begin(), names.end(), name) - names.begin();
    return test::At<float>(bytes, body + 4 * p);
  };
  EXPECT_EQ(value("x"), 1.0f);
  EXPECT_EQ(value("z"), 3.0f);
  EXPECT_EQ(value("nx"), 0.0f);
  EXPECT_EQ(value("f_dc_1"), 100.0f);  // G, coefficient 0
  // f_rest_j: channel j / 8, coefficient j % 8 + 1.
  EXPECT_EQ(value("f_rest_0"), 1.0f);     // R, coefficient 1
  EXPECT_EQ(value("f_rest_7"), 8.0f);     // R, coefficient 8
  EXPECT_EQ(value("f_rest_8"), 101.0f);   // G, coefficient 1
  EXPECT_EQ(value("f_rest_23"), 208.0f);  // B, coefficient 8
  EXPECT_EQ(value("opacity"), 1.5f);
  EXPECT_EQ(value("scale_2"), -3.0f);
  EXPECT_EQ(value("rot_0"), 0.5f);  // w first
  EXPECT_EQ(value("rot_3"), 2.0f);
}

// ASCII, shuffled order, doubles, no normals, extra properties; degree 1 with hand-placed f_rest.
TEST(SplatPly, ReadsShuffledAsciiWithExtraProperties) {
  test::ScratchDir dir;
  const std::string ply =
      "ply\nformat ascii 1.0\ncomment hand-written\nelement vertex 2\n"
      "property double rot_1\nproperty float red\nproperty double f_rest_8\nproperty float z\n"
      "property float opacity\nproperty float scale_2\nproperty float f_dc_0\nproperty float x\n"
      "property float f_rest_0\nproperty float f_rest_1\nproperty float f_rest_2\nproperty float f_rest_3\n"
      "property float f_rest_4\nproperty float f_rest_5\nproperty float f_rest_6\nproperty float f_rest_7\n"
      "property float scale_0\nproperty float scale_1\nproperty float rot_0\nproperty float rot_2\n"
      "property float rot_3\nproperty float y\nproperty float f_dc_1\nproperty float f_dc_2\n"
      "property uchar confidence\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
      // rot_1 red f_rest_8 z opacity scale_2 f_dc_0 x | f_rest_0..7 | scale_0 scale_1 rot_0 rot_2 rot_3 y dc1
      // dc2 conf
      "0.5 200 -8 3 -0.25 -3 0.1 1  1 2 3 -1 -2 -3 7 8  -1 -2 1 0 0 2 0.2 0.3 9\n"
      "0 0 0 13 +4 1 0 11 0 0 0 0 0 0 0 0 2 1.5e-1 1 0 0 12 0 0 1\r\n";
  WriteText(dir / "a.ply", ply);
  std::vector<std::string> ignored;
  Expected<splat::GaussianModel> m = ReadSplatPly((dir / "a.ply").string(), &ignored);
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(ignored, (std::vector<std::string>{"red", "confidence"}));
  ASSERT_EQ(m->sh_degree, 1);
  ASSERT_EQ(m->size(), 2u);
  EXPECT_EQ(m->positions[0], Eigen::Vector3f(1, 2, 3));
  EXPECT_EQ(m->positions[1], Eigen::Vector3f(11, 12, 13));
  EXPECT_EQ(m->log_scales[0], Eigen::Vector3f(-1, -2, -3));
  EXPECT_EQ(m->log_scales[1], Eigen::Vector3f(2, 0.15f, 1));
  EXPECT_EQ(m->opacity_logits[0], -0.25f);
  EXPECT_EQ(m->opacity_logits[1], 4.0f);
  EXPECT_EQ(m->rotations[0].w(), 1.0f);
  EXPECT_EQ(m->rotations[0].x(), 0.5f);
  // Coefficient-major: sh[k * 3 + c]. f_rest_0..2 are R's coefficients 1..3, f_rest_3..5 G's, 6..8 B's.
  const float expected[12] = {0.1f, 0.2f, 0.3f, 1, -1, 7, 2, -2, 8, 3, -3, -8};
  for (int v = 0; v < 12; ++v) EXPECT_EQ(m->sh[v], expected[v]) << v;
}

TEST(SplatPly, ReadsBigEndianAndIntegerProperties) {
  test::ScratchDir dir;
  test::PlyBuilder b;
  b.format = "binary_big_endian";
  b.AddProperties(test::StandardPropertyNames(0), "double");
  b.properties[0].first = "int";  // x as an integer
  b.rows = {b.DefaultRow(5), b.DefaultRow(-6)};
  WriteText(dir / "be.ply", b.Build());
  Expected<splat::GaussianModel> m = ReadSplatPly((dir / "be.ply").string());
  ASSERT_TRUE(m.ok()) << m.error();
  ASSERT_EQ(m->size(), 2u);
  EXPECT_EQ(m->positions[1], Eigen::Vector3f(-6, -6, -6));
  EXPECT_EQ(m->log_scales[0], Eigen::Vector3f::Constant(-1));
  EXPECT_EQ(m->sh[2], 0.25f);
}

TEST(SplatPly, EmptyModelRoundTrips) {
  test::ScratchDir dir;
  splat::GaussianModel empty;
  empty.sh_degree = 3;
  ASSERT_TRUE(WriteSplatPly(empty, (dir / "e.ply").string()).ok());
  Expected<splat::GaussianModel> m = ReadSplatPly((dir / "e.ply").string());
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->size(), 0u);
  EXPECT_EQ(m->sh_degree, 3);
}

TEST(SplatPly, WriteRejectsInvalidModelsAndKeepsTheOldFile) {
  test::ScratchDir dir;
  const std::string path = (dir / "s.ply").string();
  splat::GaussianModel model = test::RandomModel(1, 3, 5);
  ASSERT_TRUE(WriteSplatPly(model, path).ok());
  const std::vector<std::uint8_t> good = test::ReadBytes(path);
  model.opacity_logits[2] = std::nanf("");
  const Status s = WriteSplatPly(model, path);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("s.ply"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("opacity"), std::string::npos) << s.message();
  EXPECT_EQ(test::ReadBytes(path), good);
  EXPECT_EQ(dir.Entries().size(), 1u);
  EXPECT_FALSE(WriteSplatPly(test::RandomModel(0, 1, 1), (dir / "no/such/dir.ply").string()).ok());
}

}  // namespace
}  // namespace uf::exporting
