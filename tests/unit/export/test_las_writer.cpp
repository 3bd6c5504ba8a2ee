// LAS files checked field by field at the offsets of the LAS 1.4 R15 specification (Table 3: public header
// block, Table 4: VLR header, Table 11: point data record format 7). The offsets below are the
// specification's, written out here, not taken from the writer.
#include <gtest/gtest.h>

#include "export/las_writer.h"
#include "export_test_util.h"
#include "mapping/point_source.h"

namespace uf::exporting {
namespace {

using test::At;

struct LasHeaderFields {
  std::uint16_t global_encoding, header_size, record_length;
  std::uint32_t offset_to_points, vlr_count;
  std::uint8_t point_format;
  std::uint64_t point_count;
  Eigen::Vector3d scale, offset, max, min;
};

LasHeaderFields ReadHeader(const std::vector<std::uint8_t>& b) {
  EXPECT_GE(b.size(), 375u);
  EXPECT_EQ(test::StringAt(b, 0, 4), "LASF");  // file signature
  EXPECT_EQ(At<std::uint8_t>(b, 24), 1);       // version major
  EXPECT_EQ(At<std::uint8_t>(b, 25), 4);       // version minor
  LasHeaderFields h{};
  h.global_encoding = At<std::uint16_t>(b, 6);
  h.header_size = At<std::uint16_t>(b, 94);
  h.offset_to_points = At<std::uint32_t>(b, 96);
  h.vlr_count = At<std::uint32_t>(b, 100);
  h.point_format = At<std::uint8_t>(b, 104);
  h.record_length = At<std::uint16_t>(b, 105);
  // Legacy counts (107: count, 111: 5 x by return) must be 0 for formats 6-10 (no legacy compatibility).
  EXPECT_EQ(At<std::uint32_t>(b, 107), 0u);
  for (int r = 0; r < 5; ++r) EXPECT_EQ(At<std::uint32_t>(b, 111 + 4 * r), 0u);
  for (int i = 0; i < 3; ++i) {
    h.scale[i] = At<double>(b, 131 + 8 * i);
    h.offset[i] = At<double>(b, 155 + 8 * i);
    h.max[i] =
        At<double>(b, 179 + 16 * i);  // max x 179, min x 187, max y 195, min y 203, max z 211, min z 219
    h.min[i] = At<double>(b, 187 + 16 * i);
  }
  EXPECT_EQ(At<std::uint64_t>(b, 227), 0u);  // start of waveform data packet record
  EXPECT_EQ(At<std::uint64_t>(b, 235), 0u);  // start of first EVLR
  EXPECT_EQ(At<std::uint32_t>(b, 243), 0u);  // number of EVLRs
  h.point_count = At<std::uint64_t>(b, 247);
  EXPECT_EQ(At<std::uint64_t>(b, 255), h.point_count);  // points by return [1]: all first returns
  for (int r = 1; r < 15; ++r) EXPECT_EQ(At<std::uint64_t>(b, 255 + 8 * r), 0u);
  return h;
}

// Checks record `i` (format 7) against the map point it came from.
void ExpectRecord(const std::vector<std::uint8_t>& b, const LasHeaderFields& h, std::size_t i,
                  const mapping::MapPoint& p, const Eigen::Vector3d& expected_xyz) {
  const std::size_t at = h.offset_to_points + 36 * i;
  for (int k = 0; k < 3; ++k) {
    const double coordinate = At<std::int32_t>(b, at + 4 * k) * h.scale[k] + h.offset[k];
    EXPECT_NEAR(coordinate, expected_xyz[k], h.scale[k] / 2 + 1e-9) << "point " << i << " axis " << k;
  }
  EXPECT_EQ(At<std::uint16_t>(b, at + 12), std::min(65535.0f, std::round(p.intensity * 256)));
  EXPECT_EQ(At<std::uint8_t>(b, at + 14), 0x11);  // return 1 of 1
  EXPECT_EQ(At<std::uint8_t>(b, at + 15), 0);     // flags, channel, direction, edge
  EXPECT_EQ(At<std::uint8_t>(b, at + 16), 0);     // classification
  EXPECT_EQ(At<std::uint8_t>(b, at + 17), std::min<std::uint32_t>(p.count, 255));  // user data
  EXPECT_EQ(At<std::int16_t>(b, at + 18), 0);                                      // scan angle
  EXPECT_EQ(At<std::uint16_t>(b, at + 20), 7);  // point source id (set by the tests)
  EXPECT_DOUBLE_EQ(At<double>(b, at + 22), p.last_stamp * 1e-9);
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(At<std::uint16_t>(b, at + 30 + 2 * c), (p.has_color ? p.rgb[c] : 128) * 257);
}

TEST(LasWriter, HeaderAndRecordsFollowTheSpecification) {
  test::ScratchDir dir;
  std::vector<mapping::MapPoint> points = test::MakePoints(1000, Eigen::Vector3d(-40.3, 12.7, 1.1), 80.0);
  points[0].intensity = 300.0f;  // saturates at 65535
  LasOptions options;
  options.point_source_id = 7;
  ExportStats stats;
  ASSERT_TRUE(WriteLas(dir / "map.las", mapping::VectorPointSource(points, 333), options, &stats).ok());
  const std::vector<std::uint8_t> b = test::ReadBytes(dir / "map.las");
  const LasHeaderFields h = ReadHeader(b);
  EXPECT_EQ(h.header_size, 375);
  EXPECT_EQ(h.offset_to_points, 375u);
  EXPECT_EQ(h.vlr_count, 0u);
  EXPECT_EQ(h.global_encoding & (1 << 4), 0);  // no CRS, no WKT bit
  EXPECT_EQ(h.point_format, 7);
  EXPECT_EQ(h.record_length, 36);
  EXPECT_EQ(h.point_count, 1000u);
  EXPECT_EQ(b.size(), 375u + 36u * 1000u);
  EXPECT_EQ(stats.bytes, b.size());
  EXPECT_EQ(h.scale, Eigen::Vector3d::Constant(0.001));

  Eigen::AlignedBox3d truth;
  for (const mapping::MapPoint& p : points) truth.extend(p.position);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(h.offset[k], std::floor(truth.min()[k]));  // rounded minimum of the bounds
    EXPECT_NEAR(h.min[k], truth.min()[k], 0.0005 + 1e-9);
    EXPECT_NEAR(h.max[k], truth.max()[k], 0.0005 + 1e-9);
  }
  for (std::size_t i = 0; i < points.size(); ++i) ExpectRecord(b, h, i, points[i], points[i].position);
}

TEST(LasWriter, UtmOutputCarriesTheWktVlrAndTheWktBit) {
  test::ScratchDir dir;
  const Georeference georef = Georeference::Create({0.0, 3.0, 0.0}).value();
  std::vector<mapping::MapPoint> points = test::MakePoints(10, Eigen::Vector3d::Zero(), 0.0);
  LasOptions options;
  options.crs = OutputCrs::kUtm;
  options.georef = &georef;
  options.point_source_id = 7;
  ASSERT_TRUE(WriteLas(dir / "utm.las", mapping::VectorPointSource(points), options).ok());
  const std::vector<std::uint8_t> b = test::ReadBytes(dir / "utm.las");
  const LasHeaderFields h = ReadHeader(b);
  EXPECT_NE(h.global_encoding & (1 << 4), 0);  // bit 4: CRS is WKT
  EXPECT_EQ(h.vlr_count, 1u);
  // VLR header, 54 bytes right after the 375-byte public header (Table 4).
  EXPECT_EQ(At<std::uint16_t>(b, 375), 0);                   // reserved
  EXPECT_EQ(test::StringAt(b, 377, 16), "LASF_Projection");  // user id
  EXPECT_EQ(At<std::uint16_t>(b, 393), 2112);                // record id: OGC coordinate system WKT
  const std::uint16_t length = At<std::uint16_t>(b, 395);    // record length after header
  const std::string wkt = test::StringAt(b, 375 + 54, length);
  EXPECT_EQ(wkt, georef.UtmWkt());
  EXPECT_EQ(h.offset_to_points, 375u + 54u + length);
  EXPECT_EQ(b.size(), h.offset_to_points + 36u * 10u);
  for (std::size_t i = 0; i < points.size(); ++i)
    ExpectRecord(b, h, i, points[i], Eigen::Vector3d(500000, 0, 0));
}

TEST(LasWriter, CoarsensTheScaleWhenTheExtentWouldOverflowInt32) {
  test::ScratchDir dir;
  // 3000 km across: at 1 mm that is 3e9 steps, beyond int32; the scale must become 1 cm.
  std::vector<mapping::MapPoint> points = test::MakePoints(50, Eigen::Vector3d::Zero(), 3.0e6);
  LasOptions options;
  options.point_source_id = 7;
  ASSERT_TRUE(WriteLas(dir / "wide.las", mapping::VectorPointSource(points), options).ok());
  const std::vector<std::uint8_t> b = test::ReadBytes(dir / "wide.las");
  const LasHeaderFields h = ReadHeader(b);
  EXPECT_NEAR(h.scale.x(), 0.01, 1e-12);
  for (std::size_t i = 0; i < points.size(); ++i) ExpectRecord(b, h, i, points[i], points[i].position);
}

TEST(LasWriter, SkipsNonFinitePointsAndCountsOnlyWrittenOnes) {
  test::ScratchDir dir;
  std::vector<mapping::MapPoint> points = test::MakePoints(20, Eigen::Vector3d(5, 5, 5), 2.0);
  points[0].position.y() = std::nan("");
  points[0].position.x() = 1e9;  // a bogus point must not widen the header bounds either
  points[7].intensity = std::nan("");
  LasOptions options;
  options.point_source_id = 7;
  ExportStats stats;
  ASSERT_TRUE(WriteLas(dir / "nan.las", mapping::VectorPointSource(points), options, &stats).ok());
  EXPECT_EQ(stats.points_skipped_nonfinite, 1u);
  const std::vector<std::uint8_t> b = test::ReadBytes(dir / "nan.las");
  const LasHeaderFields h = ReadHeader(b);
  EXPECT_EQ(h.point_count, 19u);
  EXPECT_LT(h.max.x(), 10.0);
  EXPECT_EQ(At<std::uint16_t>(b, h.offset_to_points + 36 * 6 + 12), 0);  // NaN intensity -> 0
  points[7].intensity = 0;
  for (std::size_t i = 1; i < points.size(); ++i) ExpectRecord(b, h, i - 1, points[i], points[i].position);
}

TEST(LasWriter, RejectsBadOptionsNamingTheField) {
  LasOptions options;
  options.scale_m = -1;
  const Status s = ValidateLasOptions(options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("las.scale_m"), std::string::npos);
  EXPECT_NE(s.message().find("-1"), std::string::npos);
}

}  // namespace
}  // namespace uf::exporting
