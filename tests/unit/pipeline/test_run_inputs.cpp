// run.json written and read back (every transform bit for bit), and the errors for run folders that cannot be
// trained on: no run.json, a damaged one, no trajectory, a trajectory with NaN, no map.
#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"
#include "viewer/pipeline/run/run_record.h"
#include "viewer/pipeline/splat/splat_run_inputs.h"

namespace uf::pipeline {
namespace {

using testing::TempDir;

TEST(RunRecord, RunJsonRoundTripsEveryTransformExactly) {
  TempDir dir;
  RunRecord record;
  record.dataset = "/data/seq";
  RunFrames& f = record.frames;
  f.mode = OdometryMode::kLio, f.trajectory_frame = TrajectoryFrame::kImu,
  f.map_from = MapSource::kTrajectory;
  Vector6d xi;
  xi << 0.1, -0.2, 0.3, 0.01, 0.02, -0.03;
  f.T_imu_lidar = SE3::Exp(xi);
  f.T_estimator_body = SE3::Exp(2 * xi);
  f.T_output_body = SE3::Exp(-xi);
  f.T_map_world = SE3::Exp(0.1 * xi);
  ASSERT_TRUE(WriteRunRecord(dir.path(), record).ok());
  Expected<RunRecord> read = ReadRunRecord(dir.path());
  ASSERT_TRUE(read.ok()) << read.error();
  EXPECT_EQ(read->dataset, "/data/seq");
  EXPECT_EQ(read->frames.mode, OdometryMode::kLio);
  EXPECT_EQ(read->frames.trajectory_frame, TrajectoryFrame::kImu);
  EXPECT_EQ(read->frames.map_from, MapSource::kTrajectory);
  // Bit for bit: the splats are trained on poses made from these.
  EXPECT_EQ(read->frames.T_imu_lidar->matrix(), f.T_imu_lidar->matrix());
  EXPECT_EQ(read->frames.T_estimator_body.matrix(), f.T_estimator_body.matrix());
  EXPECT_EQ(read->frames.T_output_body.matrix(), f.T_output_body.matrix());
  EXPECT_EQ(read->frames.T_map_world.matrix(), f.T_map_world.matrix());
}

TEST(RunRecord, AFolderWithoutRunJsonIsAnErrorThatSaysToRunAgain) {
  TempDir dir;
  Expected<RunRecord> read = ReadRunRecord(dir.path());
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().find("run.json: missing"), std::string::npos) << read.error();
  EXPECT_NE(read.error().find("re-run `ultrafusion run`"), std::string::npos) << read.error();
}

TEST(RunRecord, DamagedRunJsonIsAnErrorNamingTheField) {
  TempDir dir;
  const std::string words = R"("dataset": "x", "mode": "lo", "map_from": "odometry")";
  dir.Write("run.json", "{" + words + R"(, "output_frame": "camera"})");
  EXPECT_NE(ReadRunRecord(dir.path()).error().find("output_frame 'camera'"), std::string::npos);
  dir.Write("run.json", R"({"dataset": "x"})");
  EXPECT_NE(ReadRunRecord(dir.path()).error().find("'mode' missing"), std::string::npos);
  dir.Write("run.json", "{" + words + R"(, "output_frame": "lidar"})");
  EXPECT_NE(ReadRunRecord(dir.path()).error().find("'frames' missing"), std::string::npos);
  const std::string identity = "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]";
  dir.Write("run.json", "{" + words + R"(, "output_frame": "lidar", "frames": {"T_imu_lidar": null, )" +
                            R"("T_estimator_body": )" + identity + R"(, "T_output_body": [[1, 2]], )" +
                            R"("T_map_world": )" + identity + "}}");
  EXPECT_NE(ReadRunRecord(dir.path()).error().find("frames.T_output_body: expected a 4x4 matrix"),
            std::string::npos);
  dir.Write("run.json", "{\"dataset\": ");
  EXPECT_NE(ReadRunRecord(dir.path()).error().find("not valid JSON"), std::string::npos);
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
}  // namespace uf::pipeline
