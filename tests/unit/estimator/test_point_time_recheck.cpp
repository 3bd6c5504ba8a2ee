// The point-time convention checked again when the registration degrades
// (odometry/estimator/point_times/point_time_recheck.h), on the simulator's scans whose times are derived the
// wrong way on purpose (the sensor sweeps clockwise from behind): only a rejection starts it, and its choice
// derives the later scans' times.
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "odometry/estimator/point_times/point_time_recheck.h"
#include "tests/unit/estimator/point_time_test_support.h"

namespace uf::estimator {
namespace {

using point_time_testing::kCcwBehind;
using point_time_testing::SimulatedScans;

TEST_F(SimulatedScans, ADegradedRegistrationChecksTheTimesAgain) {
  // A run deriving its times counter-clockwise (the sensor sweeps clockwise) whose start did not tell: the
  // scans pass untouched until the first rejection (a fallback guess does not count); the scans after it go
  // to the check, which picks clockwise from behind, and every later scan's times are derived with that.
  PointTimeCheckOptions options;
  options.max_scans = 8;
  Expected<PointTimeRecheck> recheck = PointTimeRecheck::Create(SimConfig(), kCcwBehind, options);
  ASSERT_TRUE(recheck.ok()) << recheck.error();
  const std::vector<LidarScan> scans = Scans(2.0, 24, kCcwBehind);
  std::vector<TrackEvent> events;
  std::optional<std::size_t> decided;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    if (i == 3) events.push_back({TrackEvent::Kind::kFallbackGuess, scans[2].stamp, "a guess"});
    if (i == 5 || i == 20) events.push_back({TrackEvent::Kind::kRejected, scans[i - 1].stamp, "rejected"});
    recheck->Notice(events);
    LidarScan scan = scans[i];
    ASSERT_TRUE(recheck->Prepare(scan).ok());
    LidarScan expected = scans[i];
    if (decided) DeriveAzimuthPointTimes(expected, expected.end - expected.stamp, kClockwiseFromBehind);
    ASSERT_EQ(scan.points.size(), expected.points.size());
    for (std::size_t k = 0; k < scan.points.size(); k += 97)
      ASSERT_EQ(scan.points[k].offset_ns, expected.points[k].offset_ns) << "scan " << i << " point " << k;
    if (!decided && recheck->result()) decided = i;
  }
  ASSERT_TRUE(decided.has_value());
  EXPECT_GE(*decided, 5u + 8u - 1u);  // the check held the anchor and 7 scans after the rejection at least
  const PointTimeRecheckResult& result = *recheck->result();
  EXPECT_EQ(result.trigger.stamp, scans[4].stamp);  // the first rejection; the second checks nothing
  EXPECT_EQ(result.check.current, kCcwBehind);
  EXPECT_EQ(result.check.chosen, kClockwiseFromBehind) << result.check.reason;
  ASSERT_TRUE(result.switched_from.has_value());
  EXPECT_EQ(*result.switched_from, scans[*decided + 1].stamp);
  EXPECT_EQ(result.Line().rfind("re-checked after the scan rejected at " + StampText(scans[4].stamp) +
                                    ": clockwise from behind: point-to-plane",
                                0),
            0u)
      << result.Line();
  EXPECT_NE(result.Line().find("on, the times are derived clockwise from behind"), std::string::npos);
  // Without a rejection or restart, nothing is checked and the scans pass as read.
  Expected<PointTimeRecheck> quiet = PointTimeRecheck::Create(SimConfig(), kCcwBehind, options);
  ASSERT_TRUE(quiet.ok());
  quiet->Notice({{TrackEvent::Kind::kFallbackGuess, scans[0].stamp, "a guess"}});
  LidarScan scan = scans[10];
  ASSERT_TRUE(quiet->Prepare(scan).ok());
  quiet->Finish();
  EXPECT_FALSE(quiet->result().has_value());
  EXPECT_EQ(scan.points[7].offset_ns, scans[10].points[7].offset_ns);
}

}  // namespace
}  // namespace uf::estimator
