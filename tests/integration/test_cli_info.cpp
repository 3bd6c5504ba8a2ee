// `ultrafusion info` on the recorded data in ../shared/data and on bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

using test::CommandResult;
using test::Ultrafusion;

nlohmann::json InfoJson(const std::string& dataset, const std::string& options = "") {
  const CommandResult result = Ultrafusion("info --json '" + dataset + "'" + options, /*merge_stderr=*/false);
  EXPECT_EQ(result.code, 0) << result.output;
  return nlohmann::json::parse(result.output, nullptr, /*allow_exceptions=*/false);
}

const nlohmann::json* StreamOfKind(const nlohmann::json& info, const std::string& kind) {
  for (const auto& s : info["streams"]) {
    if (s["kind"] == kind) return &s;
  }
  return nullptr;
}

// The rate must be what the stamps say: (count - 1) intervals between the first and last stamp.
void ExpectCountAndRate(const nlohmann::json* stream, std::int64_t count, double nominal_hz) {
  ASSERT_NE(stream, nullptr);
  EXPECT_EQ((*stream)["count"].get<std::int64_t>(), count);
  const double span_s =
      ((*stream)["last_stamp_ns"].get<std::int64_t>() - (*stream)["first_stamp_ns"].get<std::int64_t>()) *
      1e-9;
  EXPECT_NEAR((*stream)["rate_hz"].get<double>(), (count - 1) / span_s, 1e-9);
  EXPECT_NEAR((*stream)["rate_hz"].get<double>(), nominal_hz, 0.05 * nominal_hz);
}

TEST(CliInfo, HuskyBagStreamsCountsAndRates) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the Husky bag test needs it";
  const nlohmann::json info = InfoJson(data + "/husky-imu-wheel-gps/husky_watertown_2015-05-21.bag");
  ASSERT_FALSE(info.is_discarded());
  EXPECT_EQ(info["format"], "rosbag");
  ExpectCountAndRate(StreamOfKind(info, "imu"), 11865, 30);
  ExpectCountAndRate(StreamOfKind(info, "wheel"), 3952, 10);
  ExpectCountAndRate(StreamOfKind(info, "gnss"), 989, 2.5);
  EXPECT_EQ((*StreamOfKind(info, "imu"))["name"], "/imu/data");
  EXPECT_EQ((*StreamOfKind(info, "imu"))["imu_accel_unit"], "m/s^2");
  EXPECT_EQ((*StreamOfKind(info, "wheel"))["name"], "/husky_velocity_controller/odom");
  EXPECT_EQ((*StreamOfKind(info, "gnss"))["name"], "/fix");
}

TEST(CliInfo, HuskyConfigSelectsTheSameTopics) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the Husky bag test needs it";
  const CommandResult result = Ultrafusion("info --json --config " UF_SOURCE_DIR "/configs/husky.yaml " +
                                               data + "/husky-imu-wheel-gps/husky_watertown_2015-05-21.bag",
                                           false);
  ASSERT_EQ(result.code, 0) << result.output;
  const nlohmann::json info = nlohmann::json::parse(result.output);
  ASSERT_EQ(info["streams"].size(), 3u);
  EXPECT_EQ((*StreamOfKind(info, "imu"))["count"], 11865);
  EXPECT_EQ((*StreamOfKind(info, "wheel"))["count"], 3952);
  EXPECT_EQ((*StreamOfKind(info, "gnss"))["count"], 989);
}

TEST(CliInfo, ShippedConfigsLoad) {
  testing::TempDir dir;
  const std::string bag = dir.Write("empty.bag", "");
  for (const char* config : {"husky", "kitti", "euroc"}) {
    const CommandResult result = Ultrafusion(
        "info " + bag + " --format rosbag --config " UF_SOURCE_DIR "/configs/" + config + ".yaml");
    // The configs load; the empty bag is then reported as the data error (not a config error).
    EXPECT_EQ(result.code, 1);
    EXPECT_EQ(result.output.find(".yaml"), std::string::npos) << config << ": " << result.output;
  }
}

TEST(CliInfo, HuskyBagTable) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the Husky bag test needs it";
  const CommandResult result =
      Ultrafusion("info " + data + "/husky-imu-wheel-gps/husky_watertown_2015-05-21.bag");
  EXPECT_EQ(result.code, 0) << result.output;
  for (const char* expected :
       {"/imu/data", "sensor_msgs/Imu", "11865", "/fix", "989", "acceleration unit: m/s^2"}) {
    EXPECT_NE(result.output.find(expected), std::string::npos) << expected << "\n" << result.output;
  }
}

TEST(CliInfo, KittiKeyframeFolder) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the KITTI folder test needs it";
  const nlohmann::json info = InfoJson(data + "/kitti00-keyframes");
  ASSERT_FALSE(info.is_discarded());
  EXPECT_EQ(info["format"], "kitti");
  const nlohmann::json* lidar = StreamOfKind(info, "lidar");
  ASSERT_NE(lidar, nullptr);
  EXPECT_EQ((*lidar)["count"], 80);
  EXPECT_GE((*lidar)["points_per_scan"]["min"].get<int>(), 101000);
  EXPECT_LE((*lidar)["points_per_scan"]["max"].get<int>(), 127999);
  EXPECT_NE(info["ground_truth"].get<std::string>().find("groundtruth_velodyne.tum"), std::string::npos);
  // No per-point time: the azimuth convention checked on the first scans, KITTI's kept (the check's own
  // figures are tests/unit/estimator/test_point_time_check.cpp's).
  EXPECT_EQ((*lidar)["azimuth_convention"], "clockwise_from_behind");
  const nlohmann::json& times = info["point_times"];
  EXPECT_EQ(times["stream"], "velodyne");
  EXPECT_EQ(times["convention"], "clockwise_from_behind");
  EXPECT_EQ(times["source"], "chosen by the check");
  EXPECT_EQ(times["check"]["compared"], true);
  EXPECT_EQ(times["check"]["scores"].size(), 5u);
  EXPECT_EQ(times["check"]["scores"][0]["convention"], "clockwise_from_behind");
  EXPECT_EQ(times["check"]["scans_used"], 12);
  EXPECT_EQ(times["check"]["separate_sweeps"], true);  // keyframes 0.2 s apart, 0.1 s sweeps
  EXPECT_NE(times["line"].get<std::string>().find("clockwise from behind: point-to-plane"), std::string::npos)
      << times["line"];
}

TEST(CliInfo, ConfiguredPointTimeConventionIsUsedUnchecked) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: the KITTI folder test needs it";
  testing::TempDir dir;
  const std::string config = dir.File("none.yaml");
  std::ofstream(config) << "dataset:\n  point_time_convention: none\n";
  const nlohmann::json info = InfoJson(data + "/kitti00-keyframes", " --config " + config);
  EXPECT_EQ((*StreamOfKind(info, "lidar"))["azimuth_convention"], "none");
  EXPECT_EQ(info["point_times"]["source"], "dataset.point_time_convention");
  EXPECT_FALSE(info["point_times"].contains("check"));
  const CommandResult table = Ultrafusion("info " + data + "/kitti00-keyframes --config " + config);
  EXPECT_NE(table.output.find("azimuth convention: none (no deskew) (set by dataset.point_time_convention)"),
            std::string::npos)
      << table.output;
}

// The small multi-sensor bag of the fuzz seeds (written by librosbag, lz4 chunks): every sensor kind, and the
// LiDAR time conventions named.
TEST(CliInfo, EveryKindOfStreamInABag) {
  const nlohmann::json info = InfoJson(UF_SOURCE_DIR "/tests/fuzz/corpus/rosbag/mixed_lz4.bag");
  ASSERT_FALSE(info.is_discarded());
  ASSERT_EQ(info["streams"].size(), 8u);
  for (const char* kind : {"imu", "lidar", "camera", "wheel", "gnss"})
    EXPECT_NE(StreamOfKind(info, kind), nullptr) << kind;
  const nlohmann::json* points = StreamOfKind(info, "lidar");
  EXPECT_EQ((*points)["name"], "/points");
  EXPECT_EQ((*points)["point_time_field"], "time");
  EXPECT_EQ((*points)["point_time"], "float32 s relative to the scan stamp");
  EXPECT_EQ((*StreamOfKind(info, "imu"))["count"], 6);
  EXPECT_EQ((*StreamOfKind(info, "imu"))["verdict"], "ok");
}

TEST(CliInfo, TruncatedBagIsAnErrorNamingFileAndOffset) {
  testing::TempDir dir;
  std::ifstream in(UF_SOURCE_DIR "/tests/fuzz/corpus/rosbag/mixed_lz4.bag", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 5000u);
  const std::string cut = dir.Write("cut.bag", bytes.substr(0, 5000));
  const CommandResult result = Ultrafusion("info " + cut);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find(cut + ": "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("5000 bytes"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("truncated"), std::string::npos) << result.output;
}

// A EuRoC folder whose camera has a calibration in sensor.yaml and whose image files are missing: the
// intrinsics are shown, and the missing images are a counted warning, not an error.
TEST(CliInfo, EurocCalibrationAndMissingImages) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir.path() / "mav0/imu0");
  std::filesystem::create_directories(dir.path() / "mav0/cam0/data");
  dir.Write("mav0/imu0/data.csv",
            "#timestamp [ns],wx,wy,wz,ax,ay,az\n1000000000,0,0,0,0,0,9.81\n1005000000,0,0,0,0,0,9.81\n");
  dir.Write("mav0/cam0/data.csv", "#timestamp [ns],filename\n1000000000,a.png\n1050000000,b.png\n");
  dir.Write("mav0/cam0/sensor.yaml",
            "camera_model: pinhole\nintrinsics: [458.654, 457.296, 367.215, 248.375]\n"
            "distortion_model: radial-tangential\ndistortion_coefficients: [-0.28, 0.07, 0.0002, 1.8e-05]\n"
            "resolution: [752, 480]\n");
  const nlohmann::json info = InfoJson(dir.path().string());
  ASSERT_FALSE(info.is_discarded());
  EXPECT_EQ(info["format"], "euroc");
  const nlohmann::json* camera = StreamOfKind(info, "camera");
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ((*camera)["calibration"]["model"], "radial-tangential");
  EXPECT_EQ((*camera)["calibration"]["width"], 752);
  EXPECT_EQ((*camera)["calibration"]["intrinsics"][0].get<double>(), 458.654);
  EXPECT_EQ((*camera)["calibration"]["distortion"][1].get<double>(), 0.07);
  EXPECT_EQ((*camera)["count"], 0);  // both frames skipped
  ASSERT_EQ(info["warnings"].size(), 1u);
  EXPECT_EQ(info["warnings"][0]["count"], 2);
  EXPECT_EQ((*StreamOfKind(info, "imu"))["count"], 2);
}

TEST(CliInfo, MissingDatasetIsADataError) {
  const CommandResult result = Ultrafusion("info /no/such/dataset.bag");
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("/no/such/dataset.bag"), std::string::npos) << result.output;
}

TEST(CliInfo, UnrecognisedFolderSaysWhatItLookedFor) {
  testing::TempDir dir;
  dir.Write("notes.txt", "nothing here\n");
  const CommandResult result = Ultrafusion("info " + dir.path().string());
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("velodyne/"), std::string::npos) << result.output;
}

TEST(CliInfo, ConfigErrorsNameFileKeyAndValue) {
  testing::TempDir dir;
  const std::string bag = dir.Write("empty.bag", "");
  const std::string unknown = dir.Write("unknown.yaml", "dataset:\n  format: auto\n  imu_unit: g\n");
  CommandResult result = Ultrafusion("info " + bag + " --config " + unknown);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("unknown.yaml: dataset.imu_unit (line 3): unknown key"), std::string::npos)
      << result.output;

  const std::string bad_unit = dir.Write("unit.yaml", "dataset:\n  imu_accel_unit: ft/s^2\n");
  result = Ultrafusion("info " + bag + " --config " + bad_unit);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("'ft/s^2'"), std::string::npos) << result.output;

  const std::string bad_offset = dir.Write("offset.yaml", "dataset:\n  time_offsets_s: {/imu: 1e400}\n");
  result = Ultrafusion("info " + bag + " --config " + bad_offset);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("dataset.time_offsets_s./imu"), std::string::npos) << result.output;

  const std::string top = dir.Write("top.yaml", "estimator:\n  window: 10\n");
  result = Ultrafusion("info " + bag + " --config " + top);
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("unknown top-level key 'estimator'"), std::string::npos) << result.output;
}

TEST(CliInfo, UnknownFormatIsAUsageError) { EXPECT_EQ(Ultrafusion("info x.bag --format rosbag2").code, 2); }

}  // namespace
}  // namespace uf
