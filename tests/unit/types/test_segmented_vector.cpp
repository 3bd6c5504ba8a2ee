#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "odometry/types/segmented_vector.h"

namespace uf {
namespace {

TEST(SegmentedVector, HoldsWhatWasPushedInOrderAcrossSegments) {
  SegmentedVector<double> values;
  EXPECT_TRUE(values.empty());
  const std::size_t n = 3 * SegmentedVector<double>::kPerSegment + 7;
  for (std::size_t i = 0; i < n; ++i) values.push_back(0.5 * static_cast<double>(i));
  ASSERT_EQ(values.size(), n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(values[i], 0.5 * static_cast<double>(i)) << i;
  EXPECT_EQ(values.back(), 0.5 * static_cast<double>(n - 1));
  std::size_t visited = 0;
  for (const double v : values) EXPECT_EQ(v, 0.5 * static_cast<double>(visited++));
  EXPECT_EQ(visited, n);
}

TEST(SegmentedVector, NeverMovesAnElementOnceStored) {
  SegmentedVector<int> values;
  values.push_back(42);
  const int* first = &values[0];
  for (int i = 0; i < 5 * static_cast<int>(SegmentedVector<int>::kPerSegment); ++i) values.push_back(i);
  EXPECT_EQ(&values[0], first);  // a std::vector would have reallocated many times over
  EXPECT_EQ(*first, 42);
}

TEST(SegmentedVector, ElementsAreWritableInPlace) {
  SegmentedVector<int> values;
  for (int i = 0; i < 10; ++i) values.push_back(i);
  for (int& v : values) v *= 2;
  values.back() = -1;
  EXPECT_EQ(values[4], 8);
  EXPECT_EQ(values[9], -1);
}

TEST(SegmentedVector, TakeVectorMovesEverythingOutAndLeavesItEmpty) {
  SegmentedVector<std::unique_ptr<int>> owned;  // move-only elements are moved, not copied
  const std::size_t n = 2 * SegmentedVector<std::unique_ptr<int>>::kPerSegment + 1;
  for (std::size_t i = 0; i < n; ++i) owned.push_back(std::make_unique<int>(static_cast<int>(i)));
  const std::vector<std::unique_ptr<int>> all = std::move(owned).TakeVector();
  ASSERT_EQ(all.size(), n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(*all[i], static_cast<int>(i));
  EXPECT_TRUE(owned.empty());  // NOLINT(bugprone-use-after-move): the documented state after TakeVector
}

TEST(SegmentedVector, SegmentsHoldAQuarterMebibyte) {
  EXPECT_EQ(SegmentedVector<double>::kPerSegment, 32768u);
  struct Huge {
    char bytes[1 << 20];
  };
  EXPECT_EQ(SegmentedVector<Huge>::kPerSegment, 1u);  // at least one element per segment
}

}  // namespace
}  // namespace uf
