// reliability_files.h: the degenerate spans the report lists, hand-computed, and reliability.csv.
#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"
#include "viewer/pipeline/stages/reliability_files.h"

namespace uf::pipeline {
namespace {

std::vector<ScoredKeyframe> Scored(const std::vector<double>& scores) {
  std::vector<ScoredKeyframe> scored;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    ScoredKeyframe k;
    k.stamp = static_cast<Stamp>(i) * 100'000'000;
    k.lidar = LidarDegeneracy{.matches = 100, .score = scores[i]};
    scored.push_back(k);
  }
  return scored;
}

TEST(ReliabilityFiles, DegenerateSpansAreTheRunsAtOrAboveTheThreshold) {
  const std::vector<DegenerateSpan> spans = DegenerateSpans(Scored({0.1, 0.5, 0.9, 0.2, 0.0, 0.7, 0.6}), 0.5);
  ASSERT_EQ(spans.size(), 2u);
  EXPECT_EQ(spans[0].first, 100'000'000);
  EXPECT_EQ(spans[0].last, 200'000'000);
  EXPECT_EQ(spans[0].keyframes, 2);
  EXPECT_DOUBLE_EQ(spans[0].worst, 0.9);
  EXPECT_EQ(spans[1].first, 500'000'000);
  EXPECT_EQ(spans[1].last, 600'000'000);
  EXPECT_EQ(spans[1].keyframes, 2);
  EXPECT_DOUBLE_EQ(spans[1].worst, 0.7);
  EXPECT_TRUE(DegenerateSpans(Scored({0.1, 0.4}), 0.5).empty());
}

TEST(ReliabilityFiles, OneRowPerKeyframeAndThePlot) {
  uf::testing::TempDir dir;
  Expected<std::vector<std::string>> written = WriteReliabilityFiles(dir.path(), Scored({0.25, 1.0}));
  ASSERT_TRUE(written) << written.error();
  EXPECT_EQ(*written, (std::vector<std::string>{"reliability.csv", "plots/reliability_lidar.png"}));
  EXPECT_EQ(
      uf::testing::ReadText(dir.File("reliability.csv")),
      "stamp_ns,modality,score,active,matches,translation_isotropy,rotation_isotropy,weak_x,weak_y,weak_z,"
      "speed_error_mps,yaw_rate_error_rad_s\n"
      "0,lidar,0.2500,1,100,0.00000,0.00000,0.0000,0.0000,0.0000,,\n"
      "100000000,lidar,1.0000,1,100,0.00000,0.00000,0.0000,0.0000,0.0000,,\n");
  // Nothing scored (every scan rejected): the header alone, no plot.
  uf::testing::TempDir empty;
  written = WriteReliabilityFiles(empty.path(), {});
  ASSERT_TRUE(written);
  EXPECT_EQ(written->size(), 1u);
}

}  // namespace
}  // namespace uf::pipeline
