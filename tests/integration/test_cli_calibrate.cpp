// `ultrafusion calibrate` as a user runs it: a simulated rig whose LiDAR stamps run 150 ms early and whose
// given extrinsic is 5 deg off, estimated against the simulator's calibration_true.yaml; bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "odometry/io/calibration_file.h"
#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::TempDir;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

const SensorCalibration& Lidar(const Calibration& c) {
  const SensorCalibration* lidar = c.Find("lidar");
  EXPECT_NE(lidar, nullptr);
  return *lidar;
}

TEST(CliCalibrate, EstimatesTheInjectedOffsetAndRotation) {
  TempDir dir;
  const std::string seq = dir.File("seq"), out = dir.File("calib");
  const auto sim = Ultrafusion(
      "sim --scene wild --duration 30 --seed 2 --no-camera --no-gnss --no-wheel "
      "--lidar-stamp-delay -0.15 --lidar-rotation-error 5 --out " +
      seq);
  ASSERT_EQ(sim.code, 0) << sim.output;
  const auto result = Ultrafusion("calibrate " + seq + " --out " + out, false);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("time offset: locked"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("rotation: locked"), std::string::npos) << result.output;
  for (const char* file : {"calibration_estimated.yaml", "calibration_solves.csv",
                           "plots/calibration_time_offset.png", "plots/calibration_rotation.png"})
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;

  Expected<Calibration> truth = ReadCalibrationFile(seq + "/calibration_true.yaml");
  Expected<Calibration> given = ReadCalibrationFile(seq + "/calibration.yaml");
  Expected<Calibration> estimated = ReadCalibrationFile(out + "/calibration_estimated.yaml");
  ASSERT_TRUE(truth && given && estimated);
  // The figures: the offset within 5 ms, the rotation within 0.2 deg; the translation is the given
  // one.
  EXPECT_NEAR(ToSeconds(Lidar(*estimated).time_offset), ToSeconds(Lidar(*truth).time_offset), 0.005);
  const SE3& T_true = Lidar(*truth).T_body_sensor;
  const SE3& T_est = Lidar(*estimated).T_body_sensor;
  EXPECT_LT((T_true.so3().inverse() * T_est.so3()).angle(), 0.2 * kDeg);
  EXPECT_GT((T_true.so3().inverse() * Lidar(*given).T_body_sensor.so3()).angle(), 4.9 * kDeg);
  EXPECT_LT((T_est.translation() - Lidar(*given).T_body_sensor.translation()).norm(), 1e-9);
  // One line per solve after the header, each worker present.
  const std::string csv = testing::ReadText(out + "/calibration_solves.csv");
  EXPECT_NE(csv.find(",time_offset,1,"), std::string::npos);
  EXPECT_NE(csv.find(",rotation,1,"), std::string::npos);

  // The estimate applied to a LIO run (dataset.calibration_file, given relative to the working directory,
  // recorded absolute in config.yaml) against the given calibration.
  const std::string config = dir.File("estimated.yaml");
  const std::string relative = fs::relative(out + "/calibration_estimated.yaml").string();
  std::ofstream(config) << ("dataset:\n  derive_point_times_from_azimuth: false\n  calibration_file: " +
                            relative + "\nlo:\n  input_voxel_m: 0.5\n");
  auto ate = [](const std::string& output) {
    const std::size_t at = output.find("ATE (SE3-aligned RMSE): ");
    return at == std::string::npos ? -1.0 : std::stod(output.substr(at + 24));
  };
  const auto estimated_run =
      Ultrafusion("run " + seq + " --mode lio --no-map --config " + config + " --out " + dir.File("run_est"));
  ASSERT_EQ(estimated_run.code, 0) << estimated_run.output;
  EXPECT_NE(testing::ReadText(dir.File("run_est/config.yaml"))
                .find("calibration_file: \"" + fs::absolute(relative).string() + "\""),
            std::string::npos);
  const auto given_run = Ultrafusion("run " + seq + " --mode lio --no-map --config " + UF_SOURCE_DIR +
                                     "/configs/run-sim.yaml --out " + dir.File("run_given"));
  ASSERT_EQ(given_run.code, 0) << given_run.output;
  EXPECT_GT(ate(estimated_run.output), 0.0) << estimated_run.output;
  EXPECT_LT(ate(estimated_run.output), 0.5 * ate(given_run.output))
      << estimated_run.output << given_run.output;

  // Online (run --calibrate-online): the window waits for the locks (--calibration-hold, 15 s; the
  // rotation locks later); the offset locks within 5 ms and is applied, and so is the rotation once it locks
  // (run.json then records it).
  const auto online_run =
      Ultrafusion("run " + seq + " --mode lio --no-map --calibrate-online --config " + UF_SOURCE_DIR +
                  "/configs/run-sim.yaml --out " + dir.File("run_online"));
  ASSERT_EQ(online_run.code, 0) << online_run.output;
  EXPECT_NE(online_run.output.find("time offset +0.1"), std::string::npos) << online_run.output;
  EXPECT_NE(online_run.output.find("the window waited 15.0 s for the locks"), std::string::npos)
      << online_run.output;
  EXPECT_NE(online_run.output.find("rotation locked and applied"), std::string::npos) << online_run.output;
  const std::string report = testing::ReadText(dir.File("run_online/report.md"));
  EXPECT_NE(report.find("## Online calibration"), std::string::npos);
  EXPECT_NE(report.find("deg of rotation from the scan at"), std::string::npos) << report;
  Expected<Calibration> online = ReadCalibrationFile(dir.File("run_online/calibration_estimated.yaml"));
  ASSERT_TRUE(online);
  EXPECT_NEAR(ToSeconds(Lidar(*online).time_offset), ToSeconds(Lidar(*truth).time_offset), 0.005);
  // run.json's T_imu_lidar (4x4 rows) is the estimated extrinsic (IMU = the simulator's body).
  const nlohmann::json record = nlohmann::json::parse(testing::ReadText(dir.File("run_online/run.json")));
  const Eigen::Matrix4d T_online = Lidar(*online).T_body_sensor.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(record["frames"]["T_imu_lidar"][r][c].get<double>(), T_online(r, c), 1e-9) << r << c;
  EXPECT_LT(ate(online_run.output), ate(given_run.output)) << online_run.output << given_run.output;
  // Only a LIO run from the start calibrates online.
  const auto lo = Ultrafusion("run " + seq + " --mode lo --calibrate-online --out " + dir.File("run_lo"));
  EXPECT_EQ(lo.code, 2) << lo.output;
  EXPECT_NE(lo.output.find("--calibrate-online: needs a LIO run"), std::string::npos) << lo.output;
}

TEST(CliCalibrate, OnlineWithoutAHoldOnARunTooShortToLockKeepsTheGivenCalibration) {
  TempDir dir;
  const std::string seq = dir.File("seq");
  const auto sim = Ultrafusion("sim --scene wild --duration 4 --no-camera --no-gnss --no-wheel --out " + seq);
  ASSERT_EQ(sim.code, 0) << sim.output;
  const auto run =
      Ultrafusion("run " + seq + " --mode lio --no-map --calibrate-online --calibration-hold 0 --config " +
                  UF_SOURCE_DIR + "/configs/run-sim.yaml --out " + dir.File("run"));
  ASSERT_EQ(run.code, 0) << run.output;
  // 4 s cannot reach the 5 s of overlap the offset needs: nothing locks, the window never waited.
  EXPECT_NE(
      run.output.find("(the window waited 0.0 s for the locks): no time offset locked (the given one kept); "
                      "rotation not estimated (the given one kept)"),
      std::string::npos)
      << run.output;
  const std::string report = testing::ReadText(dir.File("run/report.md"));
  EXPECT_NE(report.find("- applied: nothing (the offset never locked); the run kept the given offset"),
            std::string::npos)
      << report;
  // A negative hold is refused before anything is read.
  const auto negative =
      Ultrafusion("run " + seq + " --calibrate-online --calibration-hold -1 --out " + dir.File("never"));
  EXPECT_EQ(negative.code, 2) << negative.output;
  EXPECT_NE(negative.output.find("--calibration-hold"), std::string::npos) << negative.output;
  EXPECT_FALSE(fs::exists(dir.File("never")));
}

// run with lio.estimate_lidar_translation on a hand-held walk whose given translation is 10 cm off: the
// estimate lands in calibration_estimated.yaml (nearer the truth than the given one), in imu_states.csv and
// its plot, and in the report; the settings it conflicts with are refused.
TEST(CliCalibrate, RunEstimatesTheLidarTranslation) {
  TempDir dir;
  const std::string seq = dir.File("seq");
  const auto sim = Ultrafusion(
      "sim --scene warehouse --motion handheld --lidar spinning16 --duration 8 --no-camera --no-gnss "
      "--no-wheel --lidar-translation-error 0.1 --out " +
      seq);
  ASSERT_EQ(sim.code, 0) << sim.output;
  std::string config = testing::ReadText(std::string(UF_SOURCE_DIR) + "/configs/run-sim.yaml");
  const auto set = [&config](const std::string& from, const std::string& to) {
    const std::size_t at = config.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    config.replace(at, from.size(), to);
  };
  set("  estimate_lidar_translation: false", "  estimate_lidar_translation: true");
  const std::string without_deskew = dir.File("without_deskew.yaml"), estimate = dir.File("estimate.yaml");
  std::ofstream(without_deskew) << config;
  set("  imu_deskew: false", "  imu_deskew: true");
  std::ofstream(estimate) << config;

  const auto run =
      Ultrafusion("run " + seq + " --mode lio --no-map --config " + estimate + " --out " + dir.File("run"));
  ASSERT_EQ(run.code, 0) << run.output;
  Expected<Calibration> given = ReadCalibrationFile(seq + "/calibration.yaml");
  Expected<Calibration> truth = ReadCalibrationFile(seq + "/calibration_true.yaml");
  Expected<Calibration> estimated = ReadCalibrationFile(dir.File("run/calibration_estimated.yaml"));
  ASSERT_TRUE(given && truth && estimated);
  const Eigen::Vector3d t_true = Lidar(*truth).T_body_sensor.translation();
  const double given_off = (Lidar(*given).T_body_sensor.translation() - t_true).norm();
  const double estimated_off = (Lidar(*estimated).T_body_sensor.translation() - t_true).norm();
  EXPECT_NEAR(given_off, 0.1, 1e-6);
  EXPECT_LT(estimated_off, 0.5 * given_off) << "estimated " << Lidar(*estimated).T_body_sensor.translation();
  EXPECT_LT((Lidar(*estimated).T_body_sensor.so3().inverse() * Lidar(*given).T_body_sensor.so3()).angle(),
            1e-9);
  const std::string states = testing::ReadText(dir.File("run/imu_states.csv"));
  EXPECT_NE(states.find(",lidar_tx_m,lidar_ty_m,lidar_tz_m\n"), std::string::npos) << states.substr(0, 300);
  EXPECT_TRUE(fs::exists(dir.File("run/plots/lidar_translation.png")));
  const std::string report = testing::ReadText(dir.File("run/report.md"));
  EXPECT_NE(report.find("LiDAR extrinsic translation estimated: ("), std::string::npos) << report;
  EXPECT_NE(report.find("(plots/lidar_translation.png)"), std::string::npos) << report;

  const auto no_deskew = Ultrafusion("run " + seq + " --mode lio --no-map --config " + without_deskew +
                                     " --out " + dir.File("never"));
  EXPECT_EQ(no_deskew.code, 2) << no_deskew.output;
  EXPECT_NE(no_deskew.output.find("lio.estimate_lidar_translation: needs lio.imu_deskew"), std::string::npos)
      << no_deskew.output;
  const auto online = Ultrafusion("run " + seq + " --mode lio --no-map --calibrate-online --config " +
                                  estimate + " --out " + dir.File("never"));
  EXPECT_EQ(online.code, 2) << online.output;
  EXPECT_NE(online.output.find("--calibrate-online: not with lio.estimate_lidar_translation"),
            std::string::npos)
      << online.output;
  EXPECT_FALSE(fs::exists(dir.File("never")));
}

TEST(CliCalibrate, BadInputIsAClearError) {
  TempDir dir;
  const std::string seq = dir.File("no_lidar");
  const auto sim =
      Ultrafusion("sim --scene urban --duration 2 --lidar none --no-camera --no-gnss --out " + seq);
  ASSERT_EQ(sim.code, 0) << sim.output;
  const auto no_lidar = Ultrafusion("calibrate " + seq);
  EXPECT_EQ(no_lidar.code, 1) << no_lidar.output;
  EXPECT_NE(no_lidar.output.find("calibrate needs a LiDAR stream; the dataset has imu (imu)"),
            std::string::npos)
      << no_lidar.output;
  const auto missing = Ultrafusion("calibrate " + dir.File("nothing_here"));
  EXPECT_EQ(missing.code, 1) << missing.output;
  EXPECT_NE(missing.output.find("nothing_here"), std::string::npos) << missing.output;
  const auto window = Ultrafusion("calibrate " + seq + " --window 5");
  EXPECT_EQ(window.code, 2) << window.output;
  EXPECT_NE(window.output.find("--window"), std::string::npos) << window.output;
  EXPECT_FALSE(fs::exists(dir.File("out")));
}

}  // namespace
}  // namespace uf
