// Rings recovered from the stored order of a scan (rings_from_storage_order.h), on made-up scans whose rings
// are known: stored ring by ring they come back (but for a few points where a ring starts a little before
// or after the first ring did); stored in any other order they are not guessed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "odometry/types/rings_from_storage_order.h"

namespace uf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A spinning LiDAR's scan stored ring by ring: ring r at elevation 10 - 0.5 r deg, each ring one turn of
// azimuth (counter-clockwise) from `start_deg` (+ a per-ring offset of up to 0.5 deg, as real lasers have),
// one point per `step_deg` except inside the azimuth gap [gap_from, gap_to) deg (no returns), ranges 5-40 m.
LidarScan RingOrderedScan(int rings, double start_deg, double step_deg, double gap_from = 0,
                          double gap_to = 0) {
  LidarScan scan;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> range(5, 40);
  for (int r = 0; r < rings; ++r) {
    const double elevation = (10.0 - 0.5 * r) * kPi / 180;
    const double offset = 0.5 * std::sin(r);
    for (double turned = 0; turned < 360 - step_deg / 2; turned += step_deg) {
      const double azimuth_deg = std::remainder(start_deg + offset + turned, 360.0);
      if (azimuth_deg >= gap_from && azimuth_deg < gap_to) continue;
      const double a = azimuth_deg * kPi / 180, d = range(rng);
      LidarPoint& p = scan.points.emplace_back();
      p.x = static_cast<float>(d * std::cos(elevation) * std::cos(a));
      p.y = static_cast<float>(d * std::cos(elevation) * std::sin(a));
      p.z = static_cast<float>(d * std::sin(elevation));
      p.ring = static_cast<std::uint16_t>(r);  // the truth, moved aside below
    }
  }
  return scan;
}

std::vector<std::uint16_t> TakeRings(LidarScan& scan) {
  std::vector<std::uint16_t> rings;
  for (LidarPoint& p : scan.points) rings.push_back(std::exchange(p.ring, 0));
  return rings;
}

TEST(RingsFromStorageOrder, RingByRingStorageGivesEveryPointItsRing) {
  for (const auto& [rings, start_deg] : {std::pair{16, -180.0}, std::pair{32, 5.0}, std::pair{64, 97.0}}) {
    LidarScan scan = RingOrderedScan(rings, start_deg, 0.2, 40, 100);  // 60 deg without returns
    const std::vector<std::uint16_t> truth = TakeRings(scan);
    EXPECT_EQ(DeriveRingsFromStorageOrder(scan), rings) << start_deg;
    EXPECT_TRUE(scan.has_ring);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) wrong += scan.points[i].ring != truth[i];
    // Only points within a ring's azimuth offset (<= 0.5 deg) of where the first ring started may be counted
    // to a neighbouring ring: at most 3 of the 1800 per ring.
    EXPECT_LE(wrong, 3u * rings) << rings << " rings from " << start_deg << " deg";
  }
}

TEST(RingsFromStorageOrder, AnyOtherOrderIsNotGuessed) {
  LidarScan shuffled = RingOrderedScan(32, 0, 0.2);
  std::shuffle(shuffled.points.begin(), shuffled.points.end(), std::mt19937(3));
  EXPECT_EQ(DeriveRingsFromStorageOrder(shuffled), 0);
  EXPECT_FALSE(shuffled.has_ring);

  LidarScan clockwise = RingOrderedScan(32, 0, 0.2);  // stored in the opposite direction: steps back
  std::reverse(clockwise.points.begin(), clockwise.points.end());
  EXPECT_EQ(DeriveRingsFromStorageOrder(clockwise), 0);

  LidarScan half_turn_gap = RingOrderedScan(32, 0, 0.2, -100, 100);  // 200 deg without returns: ambiguous
  EXPECT_EQ(DeriveRingsFromStorageOrder(half_turn_gap), 0);

  LidarScan few = RingOrderedScan(kMinDerivedRings - 1, 0, 0.2);
  EXPECT_EQ(DeriveRingsFromStorageOrder(few), 0);

  LidarScan spinning_on;  // 2000 points 179 deg apart: 994 turns, more rings than any LiDAR has
  for (int i = 0; i < 2000; ++i) {
    const double a = std::remainder(i * 179.0, 360.0) * kPi / 180;
    LidarPoint& p = spinning_on.points.emplace_back();
    p.x = static_cast<float>(10 * std::cos(a));
    p.y = static_cast<float>(10 * std::sin(a));
  }
  EXPECT_EQ(DeriveRingsFromStorageOrder(spinning_on), 0);

  LidarScan cut = RingOrderedScan(32, 0, 0.2);  // the last ring stops half way: not whole turns
  cut.points.resize(cut.points.size() - 900);
  EXPECT_EQ(DeriveRingsFromStorageOrder(cut), 0);

  LidarScan known = RingOrderedScan(32, 0, 0.2);  // rings the file stored win
  known.has_ring = true;
  EXPECT_EQ(DeriveRingsFromStorageOrder(known), 0);
  EXPECT_EQ(known.points.back().ring, 31);
}

}  // namespace
}  // namespace uf
