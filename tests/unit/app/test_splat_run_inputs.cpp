// run.json written and read back, and the errors for run folders that cannot be trained on: no run.json,
// a damaged one, no trajectory, a trajectory with NaN, no map.
#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"
#include "viewer/pipeline/splat/splat_run_inputs.h"

namespace uf::app {
namespace {

using testing::TempDir;

TEST(SplatRunInputs, RunJsonRoundTrips) {
  TempDir dir;
  const RunInfo info{"/data/seq", "imu", "lio", "trajectory"};
  ASSERT_TRUE(WriteRunJson(dir.path(), info).ok());
  Expected<RunInfo> read = ReadRunJson(dir.path());
  ASSERT_TRUE(read.ok()) << read.error();
  EXPECT_EQ(read->dataset, "/data/seq");
  EXPECT_EQ(read->output_frame, "imu");
  EXPECT_EQ(read->mode, "lio");
  EXPECT_EQ(read->map_from, "trajectory");
}

TEST(SplatRunInputs, AFolderWithoutRunJsonIsAnErrorThatSaysToRunAgain) {
  TempDir dir;
  Expected<RunInfo> read = ReadRunJson(dir.path());
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().find("run.json: missing"), std::string::npos) << read.error();
  EXPECT_NE(read.error().find("re-run `ultrafusion run`"), std::string::npos) << read.error();
}

TEST(SplatRunInputs, DamagedRunJsonIsAnErrorNamingTheField) {
  TempDir dir;
  dir.Write(
      "run.json",
      "{\"dataset\": \"x\", \"output_frame\": \"camera\", \"mode\": \"lo\", \"map_from\": \"odometry\"}");
  EXPECT_NE(ReadRunJson(dir.path()).error().find("output_frame 'camera'"), std::string::npos);
  dir.Write("run.json", "{\"dataset\": \"x\"}");
  EXPECT_NE(ReadRunJson(dir.path()).error().find("'output_frame' missing"), std::string::npos);
  dir.Write("run.json", "{\"dataset\": ");
  EXPECT_NE(ReadRunJson(dir.path()).error().find("not valid JSON"), std::string::npos);
}

TEST(SplatRunInputs, TrajectoriesMustExistHoldTwoPosesAndFiniteValues) {
  TempDir dir;
  EXPECT_NE(ReadSplatTrajectory(dir.File("trajectory.tum")).error().find("trajectory.tum: missing"),
            std::string::npos);
  const std::string one = dir.Write("one.tum", "1.0 0 0 0 0 0 0 1\n");
  EXPECT_NE(ReadSplatTrajectory(one).error().find("1 poses"), std::string::npos);
  const std::string nan = dir.Write("nan.tum", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n3.0 nan 0 0 0 0 0 1\n");
  Expected<Trajectory> read = ReadSplatTrajectory(nan);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().find(nan + ":3: "), std::string::npos) << read.error();  // file:line
}

TEST(SplatRunInputs, AFolderWithoutAMapIsAnErrorNamingIt) {
  TempDir dir;
  Expected<splat::SeedResult> seeded = SeedFromRunMap(dir.path(), 3, 1000);
  ASSERT_FALSE(seeded.ok());
  EXPECT_NE(seeded.error().find("map.vdb: missing"), std::string::npos) << seeded.error();
}

}  // namespace
}  // namespace uf::app
