// imu_states_file.h: imu_states.csv against hand-computed rows (also with the LiDAR translation's columns),
// its plots, and a non-finite state refused with nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "tests/support/temp_dir.h"
#include "viewer/pipeline/stages/imu_states_file.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

TEST(ImuStatesFile, OneRowPerKeyframeAndABiasPlotPerSensor) {
  uf::testing::TempDir dir;
  fs::create_directories(dir.path() / "plots");
  const std::vector<ImuStateRow> rows = {
      {1'000'000'000, {3, 4, 0}, {0.01, -0.02, 0.03}, {1e-4, -2e-4, 3e-4}, std::nullopt},
      {1'100'000'000, {0, 0, -2}, {0, 0, 0}, {0, 0, 0}, std::nullopt}};
  Expected<ImuStateFiles> written = WriteImuStateFiles(dir.path(), rows);
  ASSERT_TRUE(written.ok()) << written.error();
  EXPECT_EQ(written->files, (std::vector<std::string>{"imu_states.csv", "plots/imu_accel_bias.png",
                                                      "plots/imu_gyro_bias.png"}));
  EXPECT_EQ(written->accel_bias_plot, "plots/imu_accel_bias.png");
  EXPECT_EQ(written->gyro_bias_plot, "plots/imu_gyro_bias.png");
  EXPECT_EQ(testing::ReadText(dir.File("imu_states.csv")),
            "stamp_ns,vx_mps,vy_mps,vz_mps,speed_mps,accel_bias_x,accel_bias_y,accel_bias_z,gyro_bias_x,"
            "gyro_bias_y,gyro_bias_z\n"
            "1000000000,3.000000,4.000000,0.000000,5.000000,0.0100000,-0.0200000,0.0300000,0.00010000,"
            "-0.00020000,0.00030000\n"
            "1100000000,0.000000,0.000000,-2.000000,2.000000,0.0000000,0.0000000,0.0000000,0.00000000,"
            "0.00000000,0.00000000\n");
  for (const std::string& file : written->files) EXPECT_GT(fs::file_size(dir.path() / file), 0u) << file;
  EXPECT_TRUE(written->lidar_translation_plot.empty());
}

// With the LiDAR translation estimated: three more columns (empty in a row without it) and its plot.
TEST(ImuStatesFile, TheEstimatedLidarTranslationGetsColumnsAndAPlot) {
  uf::testing::TempDir dir;
  fs::create_directories(dir.path() / "plots");
  const std::vector<ImuStateRow> rows = {
      {1'000'000'000, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, std::nullopt},
      {1'100'000'000, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {{0.01, -0.002, 0.25}}},
      {1'200'000'000, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {{0.012, 0, 0.2475}}}};
  Expected<ImuStateFiles> written = WriteImuStateFiles(dir.path(), rows);
  ASSERT_TRUE(written.ok()) << written.error();
  EXPECT_EQ(written->lidar_translation_plot, "plots/lidar_translation.png");
  EXPECT_EQ(written->files.back(), "plots/lidar_translation.png");
  EXPECT_GT(fs::file_size(dir.path() / "plots/lidar_translation.png"), 0u);
  const std::string zeros =
      "0.000000,0.000000,0.000000,0.000000,0.0000000,0.0000000,0.0000000,0.00000000,"
      "0.00000000,0.00000000";
  EXPECT_EQ(testing::ReadText(dir.File("imu_states.csv")),
            "stamp_ns,vx_mps,vy_mps,vz_mps,speed_mps,accel_bias_x,accel_bias_y,accel_bias_z,gyro_bias_x,"
            "gyro_bias_y,gyro_bias_z,lidar_tx_m,lidar_ty_m,lidar_tz_m\n"
            "1000000000," +
                zeros +
                ",,,\n"
                "1100000000," +
                zeros +
                ",0.01000,-0.00200,0.25000\n"
                "1200000000," +
                zeros + ",0.01200,0.00000,0.24750\n");
}

TEST(ImuStatesFile, NothingForNoRowsAndNoFileForANonFiniteState) {
  uf::testing::TempDir dir;
  fs::create_directories(dir.path() / "plots");
  Expected<ImuStateFiles> none = WriteImuStateFiles(dir.path(), {});
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->files.empty());
  EXPECT_TRUE(none->accel_bias_plot.empty());
  const std::vector<ImuStateRow> rows = {{5, {0, 0, 0}, {0, std::nan(""), 0}, {0, 0, 0}, std::nullopt}};
  Expected<ImuStateFiles> bad = WriteImuStateFiles(dir.path(), rows);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("imu_states.csv"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find("not finite"), std::string::npos) << bad.error();
  EXPECT_FALSE(fs::exists(dir.path() / "imu_states.csv"));
  EXPECT_TRUE(fs::is_empty(dir.path() / "plots"));
}

}  // namespace
}  // namespace uf::pipeline
