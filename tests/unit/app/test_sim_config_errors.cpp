// The sim: section's errors name the file, the key path, the line and the bad value; the loader skips the
// calibration: section and rejects unknown top-level keys.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/temp_dir.h"
#include "viewer/app/config/config_file.h"

namespace uf::app {
namespace {

using sim::SimulationConfig;

Expected<ConfigFile> LoadText(const testing::TempDir& dir, const std::string& text) {
  return LoadConfigFile(dir.Write("sim.yaml", text));
}

// Each bad file fails with a message holding every one of `expected` (file name, key path, line, value).
struct BadFile {
  std::string text;
  std::vector<std::string> expected;
};

TEST(SimConfig, ErrorsNameTheFileTheKeyTheLineAndTheValue) {
  const std::vector<BadFile> cases = {
      {"sim:\n  lidar:\n    colour: red\n",
       {"sim.yaml: sim.lidar.colour (line 3): unknown key (expected enabled,"}},
      {"sim:\n  colour: 1\n", {"sim.colour (line 2): unknown key"}},
      {"sim:\n  gnss:\n    noise:\n      single: {horizontal: 1}\n",
       {"sim.gnss.noise.single.horizontal (line 4)"}},
      {"sim:\n  camera:\n    extrinsic: {translation: [1, 2, 3]}\n",
       {"sim.camera.extrinsic.translation (line 3): unknown key"}},
      {"sim:\n  wheel:\n    extrinsic_error: {rotation_rad: [1, 2, 3]}\n",
       {"sim.wheel.extrinsic_error.rotation_rad"}},
      {"sim:\n  imu:\n    rate_hz: fast\n",
       {"sim.yaml: sim.imu.rate_hz (line 3): expected a number, got 'fast'"}},
      {"sim:\n  camera:\n    width: 640.5\n",
       {"sim.camera.width (line 3): expected an integer, got '640.5'"}},
      {"sim:\n  seed: -1\n", {"sim.seed (line 2)", "'-1'"}},
      {"sim:\n  bag: yes\n", {"sim.bag (line 2): expected true or false, got 'yes'"}},
      {"sim:\n  lidar: 5\n", {"sim.lidar (line 2): expected a map of settings, got '5'"}},
      {"sim:\n  camera:\n    darkness: 5\n", {"sim.camera.darkness (line 3): expected a list, got '5'"}},
      {"sim:\n  imu:\n    initial_gyro_bias: [1, 2]\n",
       {"sim.imu.initial_gyro_bias (line 3): expected a list of 3 numbers, got '[1, 2]'"}},
      {"sim:\n  gnss:\n    outages:\n      - [5]\n",
       {"sim.gnss.outages[0] (line 4): expected a window [begin_s, end_s], got '[5]'"}},
      {"sim:\n  wheel:\n    floats: [[1, 2],\n             [3, 1]]\n",
       {"sim.wheel.floats[1] (line 4): the window must end after it begins, got [3, 1]"}},
      {"sim:\n  camera:\n    occlusions: [[a, 2]]\n", {"sim.camera.occlusions[0][0] (line 3)", "'a'"}},
      {"sim:\n  wheel:\n    slips: [{window: [1, 2]}]\n",
       {"sim.wheel.slips[0] (line 3): expected {window:", "ratio"}},
      {"sim:\n  wheel:\n    slips: [{window: [1, 2], ratio: 0.1, wheel: left}]\n",
       {"sim.wheel.slips[0].wheel (line 3): unknown key"}},
      {"sim:\n  gnss:\n    quality: rtk\n", {"sim.gnss.quality (line 3): unknown GNSS quality 'rtk'"}},
      {"sim:\n  gnss:\n    quality_changes: [{window: [1, 2], quality: dgps}]\n",
       {"sim.gnss.quality_changes[0].quality (line 3)", "'dgps'"}},
      {"sim:\n  lidar:\n    extrinsic: {matrix: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 2, 0,  0, 0, 0, 1]}\n",
       {"sim.lidar.extrinsic.matrix (line 3): expected a rigid transform"}},
      {"sim:\n  lidar:\n    extrinsic: {matrix: [1, 0, 0]}\n",
       {"sim.lidar.extrinsic.matrix (line 3): expected a list of 16 numbers"}},
      {"sim:\n  lidar:\n    extrinsic: {matrix: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "
       "translation_m: [1, 2, 3]}\n",
       {"sim.lidar.extrinsic (line 3): give either matrix or"}},
      {"sim:\n  trajectory: {motion: walking}\n",
       {"sim.trajectory.motion (line 2): unknown motion 'walking' (vehicle, handheld)"}},
      {"sim:\n  lidar:\n    keyframe_rate_hz: often\n",
       {"sim.lidar.keyframe_rate_hz (line 3): expected a number, got 'often'"}},
      {"sim:\n  start_time_s: noon\n",
       {"sim.start_time_s (line 2): expected a number of seconds, got 'noon'"}},
      {"dataset: {}\nestimator:\n  window: 10\n",
       {"sim.yaml (line 2): unknown top-level key 'estimator' (expected dataset, sim, calibration, lo, lio, "
        "wio, splat)"}},
      {"sim:\n  lidar: [1, 2\n", {"sim.yaml (line ", "YAML syntax error"}},
      {"- 1\n- 2\n", {"sim.yaml: expected a map of sections"}},
  };
  testing::TempDir dir;
  for (const BadFile& bad : cases) {
    Expected<ConfigFile> loaded = LoadText(dir, bad.text);
    ASSERT_FALSE(loaded.ok()) << bad.text;
    for (const std::string& part : bad.expected)
      EXPECT_NE(loaded.error().find(part), std::string::npos) << bad.text << "gave: " << loaded.error();
  }
  Expected<ConfigFile> missing = LoadConfigFile(dir.File("nonexistent.yaml"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("nonexistent.yaml: cannot open"), std::string::npos) << missing.error();
}

TEST(ConfigFile, ReadsEverySectionSkipsCalibrationAndRejectsUnknownOnes) {
  testing::TempDir dir;
  Expected<ConfigFile> loaded = LoadConfigFile(
      dir.Write("all.yaml", "sim:\n  seed: 3\ncalibration: {lidar: 1}\ndataset:\n  format: kitti\n"));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded->dataset.reader.format, DatasetFormat::kKittiFolder);
  EXPECT_EQ(loaded->sim.seed, 3u);

  loaded = LoadConfigFile(dir.Write("top.yaml", "dataset: {}\nestimator:\n  window: 10\n"));
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(
      loaded.error().find(
          "unknown top-level key 'estimator' (expected dataset, sim, calibration, lo, lio, wio, splat)"),
      std::string::npos)
      << loaded.error();
}

}  // namespace
}  // namespace uf::app
