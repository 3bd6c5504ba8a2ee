// Azimuth-derived point times per convention, against hand-computed times: a point at azimuth a (atan2(y,
// x), x forward, y left) over a 100 ms sweep; the seam of the first point's start resolved by the hints;
// the times derived again in the other direction; none; the configuration's words.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "odometry/types/azimuth_convention.h"

namespace uf {
namespace {

constexpr Stamp kPeriod = 100'000'000;  // ns
constexpr AzimuthConvention kCcwBehind{AzimuthSweep::kCounterClockwise, SweepStart::kBehind};
constexpr AzimuthConvention kCwAhead{AzimuthSweep::kClockwise, SweepStart::kAhead};
constexpr AzimuthConvention kCcwAhead{AzimuthSweep::kCounterClockwise, SweepStart::kAhead};
constexpr AzimuthConvention kCcwFirst{AzimuthSweep::kCounterClockwise, SweepStart::kFirstPoint};

LidarPoint AtAzimuth(double degrees, std::int32_t hint_ns = 0) {
  const double a = degrees * std::numbers::pi / 180;
  LidarPoint point;
  point.x = static_cast<float>(10 * std::cos(a));
  point.y = static_cast<float>(10 * std::sin(a));
  point.offset_ns = hint_ns;
  return point;
}

// The offsets (ms) of points at `degrees` derived by `convention`.
std::vector<double> OffsetsMs(const std::vector<LidarPoint>& points, const AzimuthConvention& convention) {
  LidarScan scan;
  scan.stamp = 5'000;
  scan.points = points;
  DeriveAzimuthPointTimes(scan, kPeriod, convention);
  EXPECT_EQ(scan.end, 5'000 + kPeriod);
  EXPECT_TRUE(scan.has_point_times);
  EXPECT_TRUE(scan.point_times_from_azimuth);
  std::vector<double> ms;
  for (const LidarPoint& p : scan.points) ms.push_back(p.offset_ns / 1e6);
  return ms;
}

TEST(AzimuthConvention, FixedStartsByHand) {
  // Left (+90), right (-90), ahead (0), front-left (45), just left of behind (179).
  const std::vector<LidarPoint> points = {AtAzimuth(90), AtAzimuth(-90), AtAzimuth(0), AtAzimuth(45),
                                          AtAzimuth(179)};
  // Clockwise from behind: w = 180 - a degrees; a quarter turn after behind is the left side.
  const std::vector<double> cw_behind = OffsetsMs(points, kClockwiseFromBehind);
  const std::vector<double> ccw_behind = OffsetsMs(points, kCcwBehind);  // w = 180 + a
  const std::vector<double> cw_ahead = OffsetsMs(points, kCwAhead);      // w = -a, into [0, 360)
  const std::vector<double> ccw_ahead = OffsetsMs(points, kCcwAhead);    // w = a, into [0, 360)
  const std::vector<std::vector<double>> expected = {
      {25, 75, 50, 37.5, 1 / 3.6},    // cw behind
      {75, 25, 50, 62.5, 359 / 3.6},  // ccw behind
      {75, 25, 0, 87.5, 181 / 3.6},   // cw ahead
      {25, 75, 0, 12.5, 179 / 3.6},   // ccw ahead
  };
  const std::vector<std::vector<double>> got = {cw_behind, ccw_behind, cw_ahead, ccw_ahead};
  for (std::size_t c = 0; c < got.size(); ++c)
    for (std::size_t i = 0; i < points.size(); ++i)
      EXPECT_NEAR(got[c][i], expected[c][i], 1e-4) << "convention " << c << " point " << i;
}

TEST(AzimuthConvention, FirstPointStartAndItsSeam) {
  // The first point at +30 deg; a point 90 deg clockwise of it (-60) and one 90 deg counter-clockwise
  // (+120); near the seam, +28 (2 deg clockwise *before* the first point, i.e. swept 358 deg clockwise) and
  // +32, each with a hint early (1 ms) or late (99 ms) in the sweep.
  const std::vector<LidarPoint> points = {AtAzimuth(30, 0),           AtAzimuth(-60, 25'000'000),
                                          AtAzimuth(120, 75'000'000), AtAzimuth(32, 1'000'000),
                                          AtAzimuth(32, 99'000'000),  AtAzimuth(28, 1'000'000),
                                          AtAzimuth(28, 99'000'000)};
  const std::vector<double> cw = OffsetsMs(points, kClockwiseFromFirstPoint);
  // Clockwise: w = 30 - a. +32 sweeps 358 deg: early hint -> fired just before the first point (0), late
  // -> at 358 deg. +28 sweeps 2 deg: early -> 2 deg, late -> a whole turn on (100 ms).
  const std::vector<double> cw_expected = {0, 25, 75, 0, 358 / 3.6, 2 / 3.6, 100};
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(cw[i], cw_expected[i], 1e-4) << i;
  // Counter-clockwise: w = a - 30; -60 is three quarters on, +120 a quarter; +32 sweeps 2 deg, +28 358.
  const std::vector<double> ccw = OffsetsMs(points, kCcwFirst);
  const std::vector<double> ccw_expected = {0, 75, 25, 2 / 3.6, 100, 0, 358 / 3.6};
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(ccw[i], ccw_expected[i], 1e-4) << i;
}

TEST(AzimuthConvention, DerivedAgainInTheOtherDirectionAsFromTheHints) {
  // A sweep of 720 points in storage order (hint = position in the cloud), each at a pseudo-random azimuth
  // near where a counter-clockwise sensor starting at -100 deg fires it, +-3 deg (other lasers' offsets).
  std::vector<LidarPoint> points;
  for (int i = 0; i < 720; ++i) {
    const double jitter = 3.0 * std::sin(12.9898 * i);
    const double degrees = (i == 0 ? 0 : jitter) - 100 + 0.5 * i;
    points.push_back(AtAzimuth(degrees, static_cast<std::int32_t>(i * kPeriod / 720)));
  }
  LidarScan direct, twice;
  direct.points = twice.points = points;
  DeriveAzimuthPointTimes(direct, kPeriod, kCcwFirst);
  DeriveAzimuthPointTimes(twice, kPeriod, kClockwiseFromFirstPoint);
  DeriveAzimuthPointTimes(twice, kPeriod, kCcwFirst);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(twice.points[i].offset_ns, direct.points[i].offset_ns) << i;
    // And the right sensor's times: within the 3 deg jitter (0.83 ms) of the storage position.
    EXPECT_NEAR(direct.points[i].offset_ns, points[i].offset_ns, 3.0 / 360 * kPeriod + 2) << i;
  }
}

TEST(AzimuthConvention, NoneTakesTheMiddleOfTheSweep) {
  const std::vector<double> none = OffsetsMs({AtAzimuth(90), AtAzimuth(-170), AtAzimuth(0)}, kNoDeskew);
  for (double ms : none) EXPECT_DOUBLE_EQ(ms, 50);
}

TEST(AzimuthConvention, WordsReadBack) {
  int count = 0;
  for (const AzimuthSweep sweep :
       {AzimuthSweep::kClockwise, AzimuthSweep::kCounterClockwise, AzimuthSweep::kNone}) {
    for (const SweepStart start : {SweepStart::kBehind, SweepStart::kAhead, SweepStart::kFirstPoint}) {
      const AzimuthConvention convention{sweep, start};
      const std::optional<AzimuthConvention> read = ParseAzimuthConvention(AzimuthConventionKey(convention));
      ASSERT_TRUE(read.has_value()) << AzimuthConventionKey(convention);
      EXPECT_EQ(*read, convention);
      ++count;
    }
  }
  EXPECT_EQ(count, 9);
  EXPECT_EQ(AzimuthConventionKey(kClockwiseFromBehind), "clockwise_from_behind");
  EXPECT_EQ(AzimuthConventionKey(kCcwFirst), "counter_clockwise_from_first_point");
  EXPECT_EQ(AzimuthConventionKey(kNoDeskew), "none");
  EXPECT_EQ(AzimuthConventionText(kCcwBehind), "counter-clockwise from behind");
  EXPECT_EQ(AzimuthConventionText(kNoDeskew), "none (no deskew)");
  EXPECT_FALSE(ParseAzimuthConvention("clockwise").has_value());
  EXPECT_FALSE(ParseAzimuthConvention("auto").has_value());
  EXPECT_EQ(Reversed(kClockwiseFromBehind), kCcwBehind);
  EXPECT_EQ(Reversed(kNoDeskew), kNoDeskew);
}

}  // namespace
}  // namespace uf
