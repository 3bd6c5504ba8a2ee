// reliability_files.h: the degenerate spans the report lists, hand-computed, and reliability.csv.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

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
  Expected<ReliabilityFiles> written = WriteReliabilityFiles(dir.path(), Scored({0.25, 1.0}));
  ASSERT_TRUE(written) << written.error();
  EXPECT_EQ(written->files, (std::vector<std::string>{"reliability.csv", "plots/reliability_lidar.png"}));
  EXPECT_EQ(written->lidar_plot, "plots/reliability_lidar.png");
  EXPECT_TRUE(written->wheel_plot.empty() && written->gnss_plot.empty() && written->imu_plot.empty() &&
              written->camera_plot.empty());
  EXPECT_EQ(
      uf::testing::ReadText(dir.File("reliability.csv")),
      "stamp_ns,modality,score,active,matches,translation_isotropy,rotation_isotropy,weak_x,weak_y,weak_z,"
      "speed_error_mps,speed_change_error_mps,yaw_rate_error_rad_s,fix_quality,covariance_trace_m2,"
      "innovation_d2,excitation,preintegration_chi2,clipped_steps,tracks_checked,tracks_agreeing,"
      "grid_occupancy,motion_error_px\n"
      "0,lidar,0.2500,1,100,0.00000,0.00000,0.0000,0.0000,0.0000,,,,,,,,,,,,,\n"
      "100000000,lidar,1.0000,1,100,0.00000,0.00000,0.0000,0.0000,0.0000,,,,,,,,,,,,,\n");
  // Nothing scored (every scan rejected): the header alone, no plot.
  uf::testing::TempDir empty;
  written = WriteReliabilityFiles(empty.path(), {});
  ASSERT_TRUE(written);
  EXPECT_EQ(written->files, std::vector<std::string>{"reliability.csv"});
  EXPECT_TRUE(written->lidar_plot.empty());
}

// The wheel's, the GNSS fixes', the IMU's and the camera frames' rows beside the LiDAR's: every row has the
// header's columns, each modality its own filled; the fixes and frames at their own stamps; a plot per
// modality.
TEST(ReliabilityFiles, WheelGnssImuAndCameraRowsAndPlots) {
  ScoredKeyframe k;
  k.stamp = 2'000'000'000;
  k.wheel = WheelConsistency{.speed_error_mps = 0.12,
                             .speed_change_error_mps = 0.3,
                             .yaw_rate_error_rad_s = 0.05,
                             .score = 0.4,
                             .active = false};
  k.gnss = {GnssCheck{.stamp = 1'950'000'000,
                      .fix_quality = 0.25,
                      .covariance_trace_m2 = 13.5,
                      .innovation_d2 = 2.5,
                      .score = 0.6,
                      .active = true}};
  k.imu = ImuReliability{.excitation = 0.5, .preintegration_chi2 = 3.25, .clipped_steps = 4, .score = 0.6};
  k.camera = {CameraCheck{.stamp = 1'900'000'000,
                          .tracks_checked = 60,
                          .tracks_agreeing = 18,
                          .grid_occupancy = 0.15625,
                          .motion_error_px = 25.5,
                          .score = 1.0,
                          .active = false},
              CameraCheck{.stamp = 2'000'000'000,
                          .tracks_checked = 70,
                          .tracks_agreeing = 69,
                          .grid_occupancy = 0.5,
                          .motion_error_px = 0.25,
                          .score = 0.15,
                          .active = true}};
  uf::testing::TempDir dir;
  Expected<ReliabilityFiles> written = WriteReliabilityFiles(dir.path(), {k});
  ASSERT_TRUE(written) << written.error();
  EXPECT_EQ(written->files,
            (std::vector<std::string>{"reliability.csv", "plots/reliability_wheel.png",
                                      "plots/reliability_gnss.png", "plots/reliability_imu.png",
                                      "plots/reliability_camera.png"}));
  EXPECT_TRUE(written->lidar_plot.empty());
  EXPECT_EQ(written->wheel_plot, "plots/reliability_wheel.png");
  EXPECT_EQ(written->gnss_plot, "plots/reliability_gnss.png");
  EXPECT_EQ(written->imu_plot, "plots/reliability_imu.png");
  EXPECT_EQ(written->camera_plot, "plots/reliability_camera.png");
  const std::string csv = uf::testing::ReadText(dir.File("reliability.csv"));
  EXPECT_NE(csv.find("\n2000000000,wheel,0.4000,0,,,,,,,0.1200,0.3000,0.0500,,,,,,,,,,\n"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\n1950000000,gnss,0.6000,1,,,,,,,,,,0.25,13.5000,2.500,,,,,,,\n"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\n2000000000,imu,0.6000,1,,,,,,,,,,,,,0.5000,3.250,4,,,,\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n1900000000,camera,1.0000,0,,,,,,,,,,,,,,,,60,18,0.1562,25.500\n"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\n2000000000,camera,0.1500,1,,,,,,,,,,,,,,,,70,69,0.5000,0.250\n"), std::string::npos)
      << csv;
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);)
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 22) << line;
  // Only the wheel's rows are spans of suppression, only the IMU's clipped ones spans of clipping.
  const std::vector<DegenerateSpan> spans = SuppressedWheelSpans({k});
  ASSERT_EQ(spans.size(), 1u);
  EXPECT_DOUBLE_EQ(spans[0].worst, 0.4);
  ASSERT_EQ(ClippedImuSpans({k}).size(), 1u);
  // The camera's left-out frames, at their own stamps.
  const std::vector<DegenerateSpan> frames = SuppressedCameraSpans({k});
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].first, 1'900'000'000);
  EXPECT_EQ(frames[0].last, 1'900'000'000);
  EXPECT_EQ(frames[0].keyframes, 1);
  EXPECT_DOUBLE_EQ(frames[0].worst, 1.0);
  k.imu->clipped_steps = 0;
  EXPECT_TRUE(ClippedImuSpans({k}).empty());
}

}  // namespace
}  // namespace uf::pipeline
