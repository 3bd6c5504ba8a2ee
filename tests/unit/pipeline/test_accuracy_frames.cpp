// The accuracy stage compares trajectory.tum with the ground truth in trajectory.tum's frame: a ground-truth
// file of the body frame is taken to the LiDAR's frame first when the run wrote LiDAR poses (LO). Truth: a
// tilting body with a LiDAR 0.25 m above it, the estimate its exact LiDAR poses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"
#include "viewer/pipeline/progress_line.h"
#include "viewer/pipeline/stages/accuracy_stage.h"

namespace uf::pipeline {
namespace {

// 10 s walking forward at 1 m/s while pitching and rolling by up to 15 deg, a pose every 0.05 s.
Trajectory TiltingBody() {
  Trajectory truth;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.05 * k;
    const Eigen::Vector3d tilt(0.26 * std::sin(2.1 * t), 0.26 * std::sin(1.3 * t + 1), 0.1 * t);
    truth.stamps.push_back(1'700'000'000'000'000'000 + k * 50'000'000LL);
    truth.poses.emplace_back(SO3::Exp(tilt), Eigen::Vector3d(t, 0.2 * std::sin(t), 0));
  }
  return truth;
}

struct Evaluated {
  GroundTruthCheck check;
  StageRecord record;
};

// The stage on a folder holding `estimate` as trajectory.tum, with the body-frame truth beside the dataset.
Evaluated Evaluate(const testing::TempDir& dir, const Trajectory& truth, const Trajectory& estimate,
                   const SE3& T_output_body) {
  EXPECT_TRUE(WriteTumTrajectory(dir.File("groundtruth.tum"), truth).ok());
  EXPECT_TRUE(WriteTumTrajectory(dir.File("trajectory.tum"), estimate).ok());
  DatasetDescription description;
  description.ground_truth = dir.File("groundtruth.tum");
  ProgressLine progress("test");
  Evaluated result;
  StageContext context(progress, result.record);
  result.check =
      RunAccuracyStage(description, dir.path(), std::nullopt, GnssTrackInput{}, T_output_body, context);
  return result;
}

TEST(AccuracyFrames, BodyGroundTruthIsTakenToTheLidarFrame) {
  const SE3 T_body_lidar(SO3(), Eigen::Vector3d(0, 0, 0.25));
  const Trajectory truth = TiltingBody();
  Trajectory lidar = truth;
  for (SE3& pose : lidar.poses) pose = pose * T_body_lidar;
  // LO writes the LiDAR's poses in the world of its first one: another world, which the SE3 alignment takes.
  const SE3 T_lidar0_world = lidar.poses.front().inverse();
  for (SE3& pose : lidar.poses) pose = T_lidar0_world * pose;

  testing::TempDir dir;
  const Evaluated moved = Evaluate(dir, truth, lidar, T_body_lidar.inverse());
  ASSERT_TRUE(moved.check.evaluated) << moved.check.note;
  EXPECT_TRUE(moved.check.ground_truth_moved_to_output_frame);
  EXPECT_EQ(moved.check.matched_poses, 201u);
  EXPECT_LT(moved.check.ape_rmse_m, 1e-6);  // the exact LiDAR poses
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "reference.tum"));
  EXPECT_NE(std::find(moved.record.outputs.begin(), moved.record.outputs.end(), "reference.tum"),
            moved.record.outputs.end());

  // Compared with the body's poses as they are, the lever arm swinging by +-15 deg would show as error.
  testing::TempDir raw_dir;
  const Evaluated raw = Evaluate(raw_dir, truth, lidar, SE3());
  ASSERT_TRUE(raw.check.evaluated) << raw.check.note;
  EXPECT_FALSE(raw.check.ground_truth_moved_to_output_frame);
  EXPECT_GT(raw.check.ape_rmse_m, 0.02);
  EXPECT_FALSE(std::filesystem::exists(raw_dir.path() / "reference.tum"));
}

TEST(AccuracyFrames, AnUnreadableGroundTruthIsANoteNotAFailure) {
  testing::TempDir dir;
  const Trajectory truth = TiltingBody();
  ASSERT_TRUE(WriteTumTrajectory(dir.File("trajectory.tum"), truth).ok());
  dir.Write("groundtruth.tum", "1700000000.0 0 0 nan 0 0 0 1\n");
  DatasetDescription description;
  description.ground_truth = dir.File("groundtruth.tum");
  ProgressLine progress("test");
  StageRecord record;
  StageContext context(progress, record);
  const GroundTruthCheck check = RunAccuracyStage(description, dir.path(), std::nullopt, GnssTrackInput{},
                                                  SE3(SO3(), Eigen::Vector3d(0, 0, -0.25)), context);
  EXPECT_FALSE(check.evaluated);
  EXPECT_NE(check.note.find("groundtruth.tum"), std::string::npos) << check.note;
  EXPECT_NE(record.message.find("not evaluated"), std::string::npos) << record.message;
}

}  // namespace
}  // namespace uf::pipeline
