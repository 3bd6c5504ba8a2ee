// The configuration schema as a whole: every section's emitted text reads back to every field (defaults
// over a base that differs everywhere, and the reverse), docs/CONFIG.md is what the schemas generate, every
// file in configs/ reads, the profiles that say they state defaults do, and errors of the dataset:, lo:
// and lio: sections name file, key, line and value.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "tests/support/temp_dir.h"
#include "tests/unit/app/config_samples.h"
#include "tests/unit/app/expect_config_error.h"
#include "tests/unit/app/expect_same_config.h"
#include "viewer/app/config/config_doc.h"
#include "viewer/app/config/config_file.h"
#include "viewer/app/config/render_camera.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

// Every section of `config` as one file (lio: and wio: included).
std::string EmitEverySection(const ConfigFile& config) {
  estimator::LidarOdometryConfig odometry = config.odometry;
  odometry.use_imu = true;
  return EmitDatasetConfig(config.dataset) + EmitLidarOdometryConfig(odometry) +
         EmitInertialOdometryConfig(config.wio) + EmitSplatConfig(config.splat) + EmitSimConfig(config.sim);
}

void ExpectSameSections(const ConfigFile& a, const ConfigFile& b) {
  test::ExpectSameDataset(a.dataset, b.dataset);
  test::ExpectSameLo(a.odometry, b.odometry);
  test::ExpectSameLio(a.odometry, b.odometry);
  test::ExpectSameWio(a.wio, b.wio);
  test::ExpectSameSplat(a.splat, b.splat);
  test::ExpectSameConfig(a.sim, b.sim);
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(ConfigSchema, TheSamplesDifferFromTheDefaultsInEveryKey) {
  // Otherwise the round trips below would not show that each key reaches its field. The texts are the same
  // keys in the same order, but for the samples' topics and time offsets (lists the defaults leave out).
  const std::vector<std::string> defaults = Lines(EmitEverySection(ConfigFile{}));
  std::vector<std::string> samples;
  for (const std::string& line : Lines(EmitEverySection(test::NonDefaultConfigFile())))
    if (line != "  topics:" && line != "  time_offsets_s:" && !line.starts_with("    - {topic: ") &&
        !line.starts_with("    \""))
      samples.push_back(line);
  ASSERT_EQ(defaults.size(), samples.size());
  for (std::size_t i = 0; i < defaults.size(); ++i) {
    const bool header = defaults[i].starts_with("#") || defaults[i].ends_with(":");  // comments, groups
    if (header)
      EXPECT_EQ(defaults[i], samples[i]);
    else
      EXPECT_NE(defaults[i], samples[i]);
  }
}

TEST(ConfigSchema, EmittedDefaultsReadBackAsTheDefaultsOverADifferentBase) {
  TempDir dir;
  const std::string text = EmitEverySection(ConfigFile{});
  // Empty topic and time offset lists are left out of the file (config.yaml as runs always wrote it): a
  // base's lists stay. Every other key is written.
  EXPECT_EQ(text.find("topics"), std::string::npos);
  EXPECT_EQ(text.find("time_offsets_s"), std::string::npos);
  ConfigFile base = test::NonDefaultConfigFile();
  base.dataset.reader.topics.clear();
  base.dataset.stream.time_offsets.clear();
  Expected<ConfigFile> loaded = LoadConfigFile(dir.Write("defaults.yaml", text), base);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  ExpectSameSections(*loaded, ConfigFile{});
}

TEST(ConfigSchema, EveryKeyReadsBackFromTheEmittedText) {
  TempDir dir;
  const ConfigFile samples = test::NonDefaultConfigFile();
  const std::string text = EmitEverySection(samples);
  Expected<ConfigFile> loaded = LoadConfigFile(dir.Write("samples.yaml", text));
  ASSERT_TRUE(loaded.ok()) << loaded.error() << "\n" << text;
  ExpectSameSections(*loaded, samples);
  EXPECT_EQ(EmitEverySection(*loaded), text);
}

TEST(ConfigSchema, RunsConfigYamlReadsBackWithoutTheLioSectionInLo) {
  // `run` saves dataset:, lo: and splat: (lio: only for LIO); the lio: keys keep their defaults.
  TempDir dir;
  const ConfigFile samples = test::NonDefaultConfigFile();
  const std::string text = EmitDatasetConfig(samples.dataset) + EmitLidarOdometryConfig(samples.odometry) +
                           EmitSplatConfig(samples.splat);
  EXPECT_EQ(text.find("lio:"), std::string::npos);
  Expected<ConfigFile> loaded = LoadConfigFile(dir.Write("config.yaml", text));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  test::ExpectSameDataset(loaded->dataset, samples.dataset);
  test::ExpectSameLo(loaded->odometry, samples.odometry);
  test::ExpectSameLio(loaded->odometry, estimator::LidarOdometryConfig{});
  test::ExpectSameSplat(loaded->splat, samples.splat);
}

TEST(ConfigSchema, AnLoRunWithWheelFactorsSavesTheWheelKeys) {
  // lwo reads lio.wheel: its config.yaml carries the lio: section, which reads back to the same wheel keys.
  TempDir dir;
  const ConfigFile samples = test::NonDefaultConfigFile();
  estimator::LidarOdometryConfig lwo = samples.odometry;
  lwo.use_wheel = true;
  const std::string text = EmitLidarOdometryConfig(lwo);
  EXPECT_NE(text.find("lio:"), std::string::npos);
  Expected<ConfigFile> loaded = LoadConfigFile(dir.Write("config.yaml", text));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded->odometry.wheel.forward_velocity_density, samples.odometry.wheel.forward_velocity_density);
  EXPECT_EQ(loaded->odometry.wheel.scale_prior_sigma, samples.odometry.wheel.scale_prior_sigma);
}

// The lines of `a` and `b` around the first one that differs, for the failure message.
std::string FirstDifference(const std::string& a, const std::string& b) {
  const std::vector<std::string> la = Lines(a), lb = Lines(b);
  for (std::size_t i = 0; i < std::max(la.size(), lb.size()); ++i) {
    const std::string x = i < la.size() ? la[i] : "<end>", y = i < lb.size() ? lb[i] : "<end>";
    if (x != y) return "line " + std::to_string(i + 1) + ":\n  file:      " + x + "\n  generated: " + y;
  }
  return "";
}

TEST(ConfigReference, DocsConfigMdIsWhatTheSchemasGenerate) {
  const std::string file = std::string(UF_SOURCE_DIR) + "/docs/CONFIG.md";
  const std::string text = testing::ReadText(file), generated = ConfigReferenceMarkdown();
  EXPECT_TRUE(text == generated) << "docs/CONFIG.md differs from the schemas ("
                                 << FirstDifference(text, generated)
                                 << ")\nregenerate it: cmake --build build --target config-doc";
}

TEST(ConfigReference, TheTablesStateTheCodesDefaults) {
  const std::string generated = ConfigReferenceMarkdown();
  for (const char* row :
       {"| `lo.map_insert_voxel_m` | `0.5` | m |", "| `lo.association_rounds` | `10` | rounds |",
        "| `lo.window_size` | `10` | scans |", "| `lio.imu.gravity` | `9.80665` | m/s^2 |",
        "| `splat.iterations` | `3000` | steps |", "| `splat.resolution` | `[0, 0]` | px |",
        "| `dataset.format` | `auto` | - |", "| `sim.start_time_s` | `1700000000` |",
        "| `sim.camera.extrinsic` | `{translation_m: [0.3, 0, 0.1], rotation_rpy_deg: [-90, 0, -90]}` |"})
    EXPECT_NE(generated.find(row), std::string::npos) << row;
}

// The rows "| `KEY` | DEFAULT | ..." of the Markdown tables in `text` whose key starts with lo. or lio.:
// key -> default, backticks removed.
std::map<std::string, std::string> OdometryDefaults(const std::string& text) {
  std::map<std::string, std::string> rows;
  for (const std::string& line : Lines(text)) {
    if (!line.starts_with("| `lo.") && !line.starts_with("| `lio.")) continue;
    const std::size_t key_end = line.find('`', 3), cell_end = line.find(" |", key_end + 4);
    std::string value = line.substr(key_end + 4, cell_end - key_end - 4);
    std::erase(value, '`');
    rows[line.substr(3, key_end - 3)] = value;
  }
  return rows;
}

TEST(ConfigReference, MethodMdStatesTheSchemasOdometryDefaults) {
  const auto generated = OdometryDefaults(ConfigReferenceMarkdown());
  const auto method = OdometryDefaults(testing::ReadText(std::string(UF_SOURCE_DIR) + "/docs/METHOD.md"));
  EXPECT_EQ(generated.size(), 155u);  // 31 lo: keys, 124 lio: keys (9 lio.imu, 13 lio.init, 23 lio.wheel with
                                      // its 12 lio.wheel.schedule, 32 lio.gnss, 40 lio.visual with its 9
                                      // lio.visual.schedule)
  EXPECT_EQ(method.size(), generated.size());
  for (const auto& [key, value] : generated) {
    const auto row = method.find(key);
    if (row == method.end()) {
      ADD_FAILURE() << key << " is missing from the parameter table of docs/METHOD.md";
      continue;
    }
    // Numbers as numbers ("1.0" is "1"), the rest as text.
    char *end_a = nullptr, *end_b = nullptr;
    const double a = std::strtod(value.c_str(), &end_a), b = std::strtod(row->second.c_str(), &end_b);
    if (*end_a == '\0' && *end_b == '\0' && !value.empty())
      EXPECT_EQ(a, b) << key << ": docs/METHOD.md says " << row->second << ", the code " << value;
    else
      EXPECT_EQ(row->second, value) << key;
  }
}

TEST(ConfigProfiles, EveryFileInConfigsReads) {
  int files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(std::string(UF_SOURCE_DIR) + "/configs")) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    const std::string path = entry.path().string();
    if (entry.path().filename() == "render-camera.yaml") {  // a camera file, not sections
      Expected<RenderCamera> camera = LoadRenderCamera(path);
      EXPECT_TRUE(camera.ok()) << camera.error();
      continue;
    }
    Expected<ConfigFile> loaded = LoadConfigFile(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    // The lio: keys are checked for the profiles that carry them (LIO ones): a window of 4 (the real-time
    // KITTI profile) is too short for the default initialization.
    estimator::LidarOdometryConfig odometry_config = loaded->odometry;
    odometry_config.use_imu = ("\n" + testing::ReadText(path)).find("\nlio:") != std::string::npos;
    const Status odometry = odometry_config.Validate(),
                 simulation = sim::ValidateSimulationConfig(loaded->sim);
    EXPECT_TRUE(odometry.ok()) << path << ": " << odometry.message();
    EXPECT_TRUE(simulation.ok()) << path << ": " << simulation.message();
  }
  EXPECT_GE(files, 9);
}

TEST(ConfigProfiles, ProfilesThatSayTheyStateTheDefaultsDo) {
  const std::string configs = std::string(UF_SOURCE_DIR) + "/configs/";
  const ConfigFile defaults;
  Expected<ConfigFile> kitti = LoadConfigFile(configs + "kitti.yaml", test::NonDefaultConfigFile());
  ASSERT_TRUE(kitti.ok()) << kitti.error();
  // "The values are the defaults": kitti.yaml lists every lo: key.
  test::ExpectSameLo(kitti->odometry, defaults.odometry);
  EXPECT_EQ(kitti->odometry.map_insert_voxel_m, 0.5);
  EXPECT_EQ(kitti->odometry.association_rounds, 10);

  // run-sim.yaml's lio: section says "The values are the defaults" and lists every key but the bias-change
  // thresholds: over the defaults it gives the defaults, but for the smoothing of the simulator's aliasing
  // camera, which it says is not the default.
  Expected<ConfigFile> run_sim = LoadConfigFile(configs + "run-sim.yaml");
  ASSERT_TRUE(run_sim.ok()) << run_sim.error();
  EXPECT_EQ(run_sim->odometry.visual.tracker.smoothing_sigma_px, 0.8);
  EXPECT_EQ(defaults.odometry.visual.tracker.smoothing_sigma_px, 0);
  estimator::LidarOdometryConfig smoothed = defaults.odometry;
  smoothed.visual.tracker.smoothing_sigma_px = 0.8;
  test::ExpectSameLio(run_sim->odometry, smoothed);
  EXPECT_EQ(run_sim->wio.visual.tracker.smoothing_sigma_px, 0.8);

  Expected<ConfigFile> sim = LoadConfigFile(configs + "sim.yaml", test::NonDefaultConfigFile());
  ASSERT_TRUE(sim.ok()) << sim.error();
  test::ExpectSameConfig(sim->sim, defaults.sim, 1e-15);  // rpy degrees give the matrices to rounding
  Expected<ConfigFile> splat = LoadConfigFile(configs + "splat.yaml", test::NonDefaultConfigFile());
  ASSERT_TRUE(splat.ok()) << splat.error();
  test::ExpectSameSplat(splat->splat, defaults.splat);
}

TEST(ConfigSchema, ErrorsNameTheFileTheKeyTheLineAndTheValue) {
  test::ExpectConfigError(
      "dataset:\n  format: kitti\n  imu_unit: g\n",
      {"dataset.imu_unit (line 3): unknown key (expected format, topics, imu_accel_unit,"});
  test::ExpectConfigError("dataset:\n  format: velodyne\n",
                          {"dataset.format (line 2): unknown dataset format 'velodyne'"});
  test::ExpectConfigError("dataset:\n  imu_accel_unit: G\n",
                          {"dataset.imu_accel_unit (line 2): expected auto, m/s^2 or g, got 'G'"});
  test::ExpectConfigError("dataset:\n  topics:\n    - {topic: /imu, kind: radar}\n",
                          {"dataset.topics[0].kind (line 3): unknown sensor kind 'radar'"});
  test::ExpectConfigError("dataset:\n  topics:\n    - {topic: /imu}\n",
                          {"dataset.topics[0] (line 3): expected {topic: NAME, kind: KIND}"});
  test::ExpectConfigError(
      "dataset:\n  time_offsets_s: {lidar: soon}\n",
      {"dataset.time_offsets_s.lidar (line 2): expected a number of seconds, got 'soon'"});
  test::ExpectConfigError("dataset:\n  lidar_sweep_period_s: 0\n",
                          {"dataset.lidar_sweep_period_s (line 2): must be positive, got '0'"});
  test::ExpectConfigError(
      "dataset:\n  point_time_convention: anticlockwise\n",
      {"dataset.point_time_convention (line 2): expected auto | clockwise_from_behind | clockwise_from_ahead "
       "| "
       "clockwise_from_first_point | counter_clockwise_from_behind | counter_clockwise_from_ahead | "
       "counter_clockwise_from_first_point | none, got 'anticlockwise'"});
  test::ExpectConfigError("dataset:\n  reorder_window_s: -1\n",
                          {"dataset.reorder_window_s (line 2): must not be negative"});
  test::ExpectConfigError("lo:\n  window_size: 10\n  window_sise: 4\n",
                          {"lo.window_sise (line 3): unknown key (expected input_voxel_m,"});
  test::ExpectConfigError("lo:\n  window_size: 10\n  huber_m: 0.5\n  window_size: 4\n",
                          {"lo.window_size (line 4): given twice in the same section"});
  test::ExpectConfigError("lo:\n  map:\n    voxel_m: fast\n",
                          {"lo.map.voxel_m (line 3): expected a number, got 'fast'"});
  test::ExpectConfigError("lo:\n  window_size: 4.5\n",
                          {"lo.window_size (line 2): expected an integer, got '4.5'"});
  test::ExpectConfigError("lo:\n  marginalize: yes\n",
                          {"lo.marginalize (line 2): expected true or false, got 'yes'"});
  test::ExpectConfigError("lo:\n  map: 5\n", {"lo.map (line 2): expected a map of settings, got '5'"});
  test::ExpectConfigError("lo:\n  window_size: 1\n", {"lo.window_size: must be >= 2, got 1"});
  test::ExpectConfigError("lio:\n  imu:\n    gravity: [9.81]\n",
                          {"lio.imu.gravity (line 3): expected a number, got '[9.81]'"});
  test::ExpectConfigError("lio:\n  init:\n    window: 5\n",
                          {"lio.init.window (line 3): unknown key (expected min_scans,"});
  test::ExpectConfigError("splat:\n  max_gaussians: -1\n",
                          {"splat.max_gaussians (line 2): expected an integer >= 0, got '-1'"});
}

}  // namespace
}  // namespace uf::app
