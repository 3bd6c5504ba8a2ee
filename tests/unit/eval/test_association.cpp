// Association against hand-worked cases of evo's rule: nearest stamp of the longer trajectory for each stamp
// of the shorter one, first on ties, within max_dt.
#include <gtest/gtest.h>

#include "odometry/eval/association.h"

namespace uf {
namespace {

constexpr Stamp kMs = 1'000'000;

TEST(Association, NearestOfTheLongerForEachOfTheShorter) {
  const std::vector<Stamp> reference = {0, 10 * kMs, 20 * kMs, 30 * kMs, 40 * kMs};
  const std::vector<Stamp> estimate = {1 * kMs, 24 * kMs, 36 * kMs};
  const Association a = AssociateByStamp(reference, estimate, 5 * kMs);
  EXPECT_EQ(a.estimate, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(a.reference, (std::vector<std::size_t>{0, 2, 4}));
  // 36 ms is 6 ms from 30 and 4 ms from 40; with max_dt 3 ms only the first survives.
  const Association tight = AssociateByStamp(reference, estimate, 3 * kMs);
  EXPECT_EQ(tight.estimate, (std::vector<std::size_t>{0}));
}

TEST(Association, TieTakesTheFirstAndPosesMayRepeat) {
  const std::vector<Stamp> reference = {0, 10 * kMs};
  const std::vector<Stamp> estimate = {4 * kMs, 5 * kMs, 6 * kMs};  // longer: iterate over the reference
  const Association a = AssociateByStamp(reference, estimate, 10 * kMs);
  EXPECT_EQ(a.reference, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(a.estimate, (std::vector<std::size_t>{0, 2}));
  const std::vector<Stamp> short_estimate = {5 * kMs};  // 5 ms from both: the first reference stamp wins
  EXPECT_EQ(AssociateByStamp(reference, short_estimate, 10 * kMs).reference, (std::vector<std::size_t>{0}));
  const std::vector<Stamp> near_one = {1 * kMs, 2 * kMs};  // equal lengths: iterate over the estimate
  EXPECT_EQ(AssociateByStamp(reference, near_one, 10 * kMs).reference, (std::vector<std::size_t>{0, 0}));
}

TEST(Association, MaxDtIsInclusiveAndOffsetShiftsTheEstimate) {
  // Quarter seconds are exact in binary, so the float64 distances are exactly 0.25 s.
  const std::vector<Stamp> reference = {1000 * kMs, 2000 * kMs, 3000 * kMs};
  const std::vector<Stamp> estimate = {750 * kMs, 1750 * kMs, 2750 * kMs};
  EXPECT_EQ(AssociateByStamp(reference, estimate, 250 * kMs).size(), 3u);
  EXPECT_EQ(AssociateByStamp(reference, estimate, 250 * kMs - 1).size(), 0u);
  EXPECT_EQ(AssociateByStamp(reference, estimate, 1, 250 * kMs).size(), 3u);
  EXPECT_EQ(AssociateByStamp(reference, estimate, 1, -250 * kMs).size(), 0u);
}

TEST(Association, ByIndexNeedsEqualCounts) {
  EXPECT_EQ(AssociateByIndex(4, 4)->size(), 4u);
  auto mismatch = AssociateByIndex(4, 3);
  ASSERT_FALSE(mismatch);
  EXPECT_NE(mismatch.error().find("reference has 4 poses and the estimate 3"), std::string::npos);
}

}  // namespace
}  // namespace uf
