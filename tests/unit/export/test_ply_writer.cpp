// PLY files read back by an independent parser (header text + typed binary records).
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "export/ply_writer.h"
#include "export_test_util.h"
#include "mapping/point_source.h"

namespace uf::exporting {
namespace {

// A minimal PLY reader: one `vertex` element of scalar properties, binary_little_endian.
struct PlyFile {
  std::vector<std::string> comments;
  std::vector<std::pair<std::string, std::string>> properties;  // (type, name)
  std::size_t vertices = 0;
  std::vector<std::map<std::string, double>> rows;
  std::string format;
};

std::size_t TypeSize(const std::string& type) {
  static const std::map<std::string, std::size_t> sizes = {{"char", 1},   {"uchar", 1}, {"short", 2},
                                                           {"ushort", 2}, {"int", 4},   {"uint", 4},
                                                           {"float", 4},  {"double", 8}};
  EXPECT_TRUE(sizes.count(type)) << type;
  return sizes.count(type) ? sizes.at(type) : 0;
}

double ReadTyped(const std::vector<std::uint8_t>& b, std::size_t at, const std::string& type) {
  if (type == "uchar") return test::At<std::uint8_t>(b, at);
  if (type == "uint") return test::At<std::uint32_t>(b, at);
  if (type == "float") return test::At<float>(b, at);
  if (type == "double") return test::At<double>(b, at);
  ADD_FAILURE() << "unexpected type " << type;
  return 0;
}

PlyFile ReadPly(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = test::ReadBytes(path);
  const std::string text(bytes.begin(), bytes.end());
  const std::size_t end = text.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  PlyFile ply;
  std::istringstream header(text.substr(0, end));
  std::string line;
  std::getline(header, line);
  EXPECT_EQ(line, "ply");
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string version;
      words >> ply.format >> version;
      EXPECT_EQ(version, "1.0");
    } else if (keyword == "comment") {
      ply.comments.push_back(line.substr(8));
    } else if (keyword == "element") {
      std::string name;
      words >> name >> ply.vertices;
      EXPECT_EQ(name, "vertex");
    } else if (keyword == "property") {
      std::string type, name;
      words >> type >> name;
      ply.properties.emplace_back(type, name);
    }
  }
  std::size_t record = 0;
  for (const auto& [type, name] : ply.properties) record += TypeSize(type);
  const std::size_t body = end + std::string("end_header\n").size();
  EXPECT_EQ(bytes.size(), body + ply.vertices * record) << "file size does not match the header";
  if (bytes.size() != body + ply.vertices * record) return ply;
  for (std::size_t v = 0; v < ply.vertices; ++v) {
    std::map<std::string, double> row;
    std::size_t at = body + v * record;
    for (const auto& [type, name] : ply.properties) {
      row[name] = ReadTyped(bytes, at, type);
      at += TypeSize(type);
    }
    ply.rows.push_back(row);
  }
  return ply;
}

std::string PropertyType(const PlyFile& ply, const std::string& name) {
  for (const auto& [type, n] : ply.properties)
    if (n == name) return type;
  return "";
}

void ExpectSamePoint(const mapping::MapPoint& p, const std::map<std::string, double>& row, double tolerance) {
  EXPECT_NEAR(row.at("x"), p.position.x(), tolerance);
  EXPECT_NEAR(row.at("y"), p.position.y(), tolerance);
  EXPECT_NEAR(row.at("z"), p.position.z(), tolerance);
  EXPECT_EQ(row.at("has_color"), p.has_color ? 1 : 0);
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(row.at(std::string(c == 0 ? "red" : c == 1 ? "green" : "blue")), p.has_color ? p.rgb[c] : 128);
  EXPECT_EQ(row.at("intensity"), p.intensity);
  EXPECT_EQ(row.at("nx"), p.normal.x());
  EXPECT_EQ(row.at("ny"), p.normal.y());
  EXPECT_EQ(row.at("nz"), p.normal.z());
  EXPECT_EQ(row.at("count"), p.count);
}

TEST(PlyWriter, NearOriginWritesFloatsAndEveryField) {
  test::ScratchDir dir;
  const std::vector<mapping::MapPoint> points = test::MakePoints(1000, Eigen::Vector3d(10, -20, 3), 50.0);
  // Small chunks: the writer must stitch many ForEachChunk calls.
  const mapping::VectorPointSource source(points, 97);
  ExportStats stats;
  ASSERT_TRUE(WritePly(dir / "map.ply", source, {}, &stats).ok());
  EXPECT_EQ(stats.points_written, 1000u);
  EXPECT_EQ(stats.points_skipped_nonfinite, 0u);
  EXPECT_EQ(stats.bytes, std::filesystem::file_size(dir / "map.ply"));

  const PlyFile ply = ReadPly(dir / "map.ply");
  EXPECT_EQ(ply.format, "binary_little_endian");
  EXPECT_EQ(PropertyType(ply, "x"), "float");
  EXPECT_EQ(PropertyType(ply, "red"), "uchar");
  EXPECT_EQ(PropertyType(ply, "count"), "uint");
  ASSERT_EQ(ply.rows.size(), points.size());
  // float coordinates within 50 m: spacing <= 4e-6 m.
  for (std::size_t i = 0; i < points.size(); ++i) ExpectSamePoint(points[i], ply.rows[i], 1e-5);
}

TEST(PlyWriter, FarFromOriginWritesDoubles) {
  test::ScratchDir dir;
  const std::vector<mapping::MapPoint> points = test::MakePoints(200, Eigen::Vector3d(12e3, 3e3, 0), 100.0);
  ASSERT_TRUE(WritePly(dir / "far.ply", mapping::VectorPointSource(points)).ok());
  const PlyFile ply = ReadPly(dir / "far.ply");
  EXPECT_EQ(PropertyType(ply, "x"), "double");
  ASSERT_EQ(ply.rows.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) ExpectSamePoint(points[i], ply.rows[i], 0.0);

  PlyOptions options;
  options.force_double = true;
  const std::vector<mapping::MapPoint> near = test::MakePoints(10, Eigen::Vector3d::Zero(), 1.0);
  ASSERT_TRUE(WritePly(dir / "near.ply", mapping::VectorPointSource(near), options).ok());
  EXPECT_EQ(PropertyType(ReadPly(dir / "near.ply"), "z"), "double");
}

TEST(PlyWriter, SkipsAndCountsNonFinitePositions) {
  test::ScratchDir dir;
  std::vector<mapping::MapPoint> points = test::MakePoints(100, Eigen::Vector3d::Zero(), 10.0);
  points[3].position.x() = std::nan("");
  points[50].position.z() = std::numeric_limits<double>::infinity();
  ExportStats stats;
  ASSERT_TRUE(WritePly(dir / "nan.ply", mapping::VectorPointSource(points, 16), {}, &stats).ok());
  EXPECT_EQ(stats.points_written, 98u);
  EXPECT_EQ(stats.points_skipped_nonfinite, 2u);
  const PlyFile ply = ReadPly(dir / "nan.ply");
  ASSERT_EQ(ply.vertices, 98u);
  ASSERT_EQ(ply.rows.size(), 98u);
  std::size_t row = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (i != 3 && i != 50) ExpectSamePoint(points[i], ply.rows[row++], 1e-5);
}

TEST(PlyWriter, UtmOutputIsProjectedDoubleAndSaysSoInTheHeader) {
  test::ScratchDir dir;
  // Origin on the equator at zone 31's central meridian: ENU (0, 0, 0) is UTM (500000, 0, 0) exactly.
  const Georeference georef = Georeference::Create({0.0, 3.0, 0.0}).value();
  std::vector<mapping::MapPoint> points = test::MakePoints(3, Eigen::Vector3d::Zero(), 0.0);
  PlyOptions options;
  options.crs = OutputCrs::kUtm;
  options.georef = &georef;
  ASSERT_TRUE(WritePly(dir / "utm.ply", mapping::VectorPointSource(points), options).ok());
  const PlyFile ply = ReadPly(dir / "utm.ply");
  EXPECT_EQ(PropertyType(ply, "x"), "double");
  ASSERT_EQ(ply.rows.size(), 3u);
  EXPECT_NEAR(ply.rows[0].at("x"), 500000.0, 1e-6);
  EXPECT_NEAR(ply.rows[0].at("y"), 0.0, 1e-6);
  bool names_crs = false;
  for (const std::string& c : ply.comments) names_crs |= c.find("EPSG:32631") != std::string::npos;
  EXPECT_TRUE(names_crs);

  options.georef = nullptr;  // utm without a georeference: an error, no file
  EXPECT_FALSE(WritePly(dir / "bad.ply", mapping::VectorPointSource(points), options).ok());
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
}

}  // namespace
}  // namespace uf::exporting
