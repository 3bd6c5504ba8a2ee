// Bad splat PLY files: each gives an error naming the file and the field or value at fault, never a crash
// or an allocation sized by an unchecked count.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "export/splat_ply.h"
#include "export_test_util.h"
#include "splat_test_util.h"

namespace uf::exporting {
namespace {

class SplatPlyErrors : public ::testing::Test {
 protected:
  // Writes `bytes` as bad.ply and expects reading to fail with a message containing the file name and
  // each of `parts`.
  void ExpectError(const std::string& bytes, const std::vector<std::string>& parts) {
    const std::string path = (dir_ / "bad.ply").string();
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    Expected<splat::GaussianModel> m = ReadSplatPly(path);
    ASSERT_FALSE(m.ok()) << "accepted: " << bytes.substr(0, 200);
    EXPECT_NE(m.error().find("bad.ply"), std::string::npos) << m.error();
    for (const std::string& part : parts) EXPECT_NE(m.error().find(part), std::string::npos) << m.error();
  }
  // A valid binary file of degree `degree` with `n` rows, as a builder to damage.
  static test::PlyBuilder Valid(int degree = 0, int n = 3) {
    test::PlyBuilder b;
    b.AddProperties(test::StandardPropertyNames(degree));
    for (int i = 0; i < n; ++i) b.rows.push_back(b.DefaultRow(i));
    return b;
  }
  static void Remove(test::PlyBuilder& b, const std::string& name) {
    for (std::size_t p = 0; p < b.properties.size(); ++p)
      if (b.properties[p].second == name) {
        b.properties.erase(b.properties.begin() + p);
        for (auto& row : b.rows) row.erase(row.begin() + p);
        return;
      }
  }
  static void Set(test::PlyBuilder& b, int row, const std::string& name, double value) {
    for (std::size_t p = 0; p < b.properties.size(); ++p)
      if (b.properties[p].second == name) b.rows[row][p] = value;
  }
  test::ScratchDir dir_;
};

TEST_F(SplatPlyErrors, TheBuilderMakesValidFiles) {  // so that each failure below is the damage's doing
  const std::string path = (dir_ / "good.ply").string();
  std::ofstream(path, std::ios::binary) << Valid(2).Build();
  EXPECT_TRUE(ReadSplatPly(path).ok());
}

TEST_F(SplatPlyErrors, MissingRequiredProperty) {
  for (const std::string name : {"x", "f_dc_2", "opacity", "scale_1", "rot_3"}) {
    test::PlyBuilder b = Valid();
    Remove(b, name);
    ExpectError(b.Build(), {"'" + name + "' is missing"});
  }
}

TEST_F(SplatPlyErrors, WrongShCount) {
  test::PlyBuilder b = Valid(1);
  b.properties.emplace_back("float", "f_rest_9");  // 10 f_rest
  for (auto& row : b.rows) row.push_back(0);
  ExpectError(b.Build(), {"10 f_rest", "0, 9, 24 or 45"});
  test::PlyBuilder gap = Valid(1);  // 9 f_rest, but f_rest_8 renamed f_rest_12
  for (auto& p : gap.properties)
    if (p.second == "f_rest_8") p.second = "f_rest_12";
  ExpectError(gap.Build(), {"'f_rest_8' is missing"});
}

TEST_F(SplatPlyErrors, ExtraStructureThatIsNotTheLayout) {
  test::PlyBuilder duplicate = Valid();
  duplicate.properties.emplace_back("float", "x");
  for (auto& row : duplicate.rows) row.push_back(0);
  ExpectError(duplicate.Build(), {"'x' appears twice"});
  test::PlyBuilder list = Valid(0, 0);
  list.properties.emplace_back("list uchar int", "indices");
  ExpectError(list.Build(), {"'indices' is a list"});
  test::PlyBuilder compressed = Valid();
  compressed.extra_header = "element chunk 1\nproperty float min_x\n";
  ExpectError(compressed.Build(), {"'chunk'", "compressed"});
}

TEST_F(SplatPlyErrors, NonFiniteValuesNameGaussianAndField) {
  test::PlyBuilder b = Valid();
  Set(b, 1, "opacity", std::numeric_limits<double>::quiet_NaN());
  ExpectError(b.Build(), {"Gaussian 1", "opacity"});
  b = Valid();
  Set(b, 2, "y", std::numeric_limits<double>::infinity());
  ExpectError(b.Build(), {"Gaussian 2", "position"});
  b = Valid(1);
  Set(b, 0, "f_rest_4", std::numeric_limits<double>::quiet_NaN());
  ExpectError(b.Build(), {"Gaussian 0", "SH coefficient 2 channel 1"});  // f_rest_4: G, coefficient 2
  b = Valid();
  b.format = "ascii";
  Set(b, 0, "rot_2", std::numeric_limits<double>::quiet_NaN());
  ExpectError(b.Build(), {"Gaussian 0"});
}

TEST_F(SplatPlyErrors, BadScalesAndRotations) {
  test::PlyBuilder b = Valid();
  Set(b, 1, "scale_1", -std::numeric_limits<double>::infinity());  // log of a zero scale
  ExpectError(b.Build(), {"Gaussian 1", "scale_1"});
  b = Valid();
  Set(b, 0, "scale_0", 45.0);  // e^45 m
  ExpectError(b.Build(), {"Gaussian 0", "scale_0", "[-30, 30]"});
  b = Valid();
  Set(b, 2, "rot_0", 0.0);  // all four zero
  ExpectError(b.Build(), {"Gaussian 2", "rotation"});
}

TEST_F(SplatPlyErrors, TruncatedAndAbsurdCounts) {
  const std::string good = Valid(1, 4).Build();
  ExpectError(good.substr(0, good.size() - 5), {"4 vertices", "truncated"});
  test::PlyBuilder absurd = Valid(3, 1);
  absurd.declared = 1'000'000'000'000LL;  // would be ~250 TB
  ExpectError(absurd.Build(), {"1000000000000 vertices"});
  absurd.format = "ascii";
  ExpectError(absurd.Build(), {"1000000000000 vertices"});
  test::PlyBuilder ascii = Valid(0, 3);
  ascii.format = "ascii";
  const std::string text = ascii.Build();
  ExpectError(text.substr(0, text.size() - 20), {"file ends inside vertex 2"});
  ExpectError("ply\nformat ascii 1.0\nelement vertex 18446744073709551616\n", {"non-negative integer"});
}

TEST_F(SplatPlyErrors, GarbageAndBrokenHeaders) {
  ExpectError("", {"not a PLY file"});
  ExpectError(std::string("\x89PNG\r\n\x1a\n", 8) + std::string(100, '\0'), {"not a PLY file"});
  ExpectError("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n", {"end_header"});
  ExpectError("ply\nformat binary_middle_endian 1.0\nend_header\n", {"unknown format"});
  ExpectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float16 x\nend_header\n", {"unknown type"});
  ExpectError("ply\nformat ascii 1.0\nelement face 0\nend_header\n", {"no 'vertex' element"});
  ExpectError("ply\nelement vertex 0\nend_header\n", {"no 'format' line"});
  test::PlyBuilder words = Valid();
  words.format = "ascii";
  std::string text = words.Build();
  text.replace(text.rfind("0.5"), 3, "abc");
  ExpectError(text, {"vertex 2", "'opacity'", "'abc' is not a number"});
  EXPECT_FALSE(ReadSplatPly((dir_ / "missing.ply").string()).ok());
}

}  // namespace
}  // namespace uf::exporting
