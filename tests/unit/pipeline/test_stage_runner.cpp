// The stage runner of `ultrafusion run`: stages run in order, skipped ones are not called, a failing stage
// stops the pipeline and what the earlier stages wrote stays; the summary tables say which and why.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {
namespace {

TEST(PipelineStages, RunInOrderSkipWhatIsSkippedAndRecordItemsAndOutputs) {
  std::vector<std::string> called;
  const std::vector<Stage> stages = {
      {"first", "the dataset", "",
       [&](StageContext& context) {
         called.push_back("first");
         context.SetUnit("scans");
         for (int i = 1; i <= 3; ++i) context.Progress(i, 3);
         context.AddOutput("a.txt");
         return Status();
       }},
      {"second", "first's output", "--no-second",
       [&](StageContext&) {
         called.push_back("second");
         return Status();
       }},
      {"third", "first's output", "",
       [&](StageContext& context) {
         called.push_back("third");
         context.Progress(7);  // total unknown
         return Status();
       }},
  };
  ProgressLine progress("test");
  const PipelineResult result = RunStages(stages, progress, "test");
  EXPECT_EQ(called, (std::vector<std::string>{"first", "third"}));
  ASSERT_EQ(result.stages.size(), 3u);
  EXPECT_EQ(result.failure(), nullptr);
  EXPECT_EQ(result.stages[0].status, StageStatus::kOk);
  EXPECT_EQ(result.stages[0].items, 3);
  EXPECT_EQ(result.stages[0].unit, "scans");
  EXPECT_EQ(result.stages[0].outputs, std::vector<std::string>{"a.txt"});
  EXPECT_GE(result.stages[0].seconds, 0.0);
  EXPECT_EQ(result.stages[1].status, StageStatus::kSkipped);
  EXPECT_EQ(result.stages[1].message, "--no-second");
  EXPECT_EQ(result.stages[2].status, StageStatus::kOk);
  EXPECT_EQ(result.stages[2].items, 7);

  // The console table: a header and one row per stage, columns aligned (each row's status starts where
  // the header's does).
  const std::string table = FormatStageTable(result.stages);
  std::vector<std::string> lines;
  std::istringstream split(table);
  for (std::string line; std::getline(split, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u) << table;
  const std::size_t column = lines[0].find("status");
  ASSERT_NE(column, std::string::npos);
  EXPECT_EQ(lines[1].find("ok"), column) << table;
  EXPECT_EQ(lines[2].find("skipped"), column) << table;
  EXPECT_NE(lines[1].find("3 scans"), std::string::npos) << table;
  EXPECT_NE(lines[1].find("a.txt"), std::string::npos) << table;
}

TEST(PipelineStages, AFailingStageStopsTheRunAndKeepsWhatEarlierStagesWrote) {
  testing::TempDir dir;
  bool later_called = false;
  const std::vector<Stage> stages = {
      {"odometry", "the dataset", "",
       [&](StageContext& context) {
         std::ofstream(dir.path() / "trajectory.tum") << "1 0 0 0 0 0 0 1\n";
         context.AddOutput("trajectory.tum");
         return Status();
       }},
      {"map", "keyframes", "",
       [&](StageContext& context) {
         context.Progress(2, 10);
         return Status::Error("map.vdb: no space left on device");
       }},
      {"exports", "map", "",
       [&](StageContext&) {
         later_called = true;
         return Status();
       }},
  };
  ProgressLine progress("test");
  const PipelineResult result = RunStages(stages, progress, "test");
  EXPECT_FALSE(later_called);
  ASSERT_NE(result.failure(), nullptr);
  EXPECT_EQ(result.failure()->name, "map");
  EXPECT_EQ(result.failure()->message, "map.vdb: no space left on device");
  EXPECT_EQ(result.stages[1].items, 2);
  EXPECT_EQ(result.stages[2].status, StageStatus::kNotRun);
  EXPECT_EQ(result.stages[2].message, "the map stage failed");
  EXPECT_EQ(testing::ReadText(dir.File("trajectory.tum")), "1 0 0 0 0 0 0 1\n");

  // The report's table says what failed and why, and that the later stage did not run.
  const std::string md = FormatStageMarkdown(result.stages);
  EXPECT_NE(md.find("| map | keyframes | failed | 2 items |"), std::string::npos) << md;
  EXPECT_NE(md.find("| exports | map | not run | - | - | - |"), std::string::npos) << md;
  EXPECT_NE(md.find("- map failed: map.vdb: no space left on device"), std::string::npos) << md;
  EXPECT_NE(md.find("- exports not run: the map stage failed"), std::string::npos) << md;
}

TEST(PipelineStages, StageStatusNames) {
  EXPECT_EQ(StageStatusName(StageStatus::kOk), "ok");
  EXPECT_EQ(StageStatusName(StageStatus::kFailed), "failed");
  EXPECT_EQ(StageStatusName(StageStatus::kSkipped), "skipped");
  EXPECT_EQ(StageStatusName(StageStatus::kNotRun), "not run");
}

}  // namespace
}  // namespace uf::pipeline
