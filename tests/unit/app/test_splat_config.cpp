// The splat: configuration section: configs/splat.yaml states the defaults, files round-trip through
// EmitSplatConfig, and bad files give errors naming the file, the key and its line.
#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"
#include "tests/unit/app/expect_config_error.h"
#include "viewer/app/config/config_file.h"

namespace uf::app {
namespace {

using testing::TempDir;

// The splat: section of `file`.
Expected<SplatConfig> LoadSplatConfig(const std::string& file) {
  Expected<ConfigFile> loaded = LoadConfigFile(file);
  if (!loaded) return loaded.status();
  return loaded->splat;
}

TEST(SplatConfig, TheDocumentedFileStatesTheDefaults) {
  Expected<SplatConfig> loaded = LoadSplatConfig(std::string(UF_SOURCE_DIR) + "/configs/splat.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(EmitSplatConfig(*loaded), EmitSplatConfig(SplatConfig{}));
}

TEST(SplatConfig, TheRunProfileOfTheSimulatorCarriesAShortBudget) {
  Expected<SplatConfig> loaded = LoadSplatConfig(std::string(UF_SOURCE_DIR) + "/configs/run-sim.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_GT(loaded->time_budget_s, 0);
  EXPECT_LT(loaded->training.iterations, SplatConfig{}.training.iterations);
}

TEST(SplatConfig, EveryKeyRoundTripsThroughTheEmittedText) {
  SplatConfig config;
  config.training.iterations = 123;
  config.training.sh_degree = 1;
  config.training.lr_position_initial = 3.25e-4;
  config.training.depth_weight = 0.1;
  config.training.max_gaussians = 12345;
  config.training.render.background = Eigen::Vector3f(0.25f, 0.5f, 1.0f);
  config.training.seed = 99;
  config.time_budget_s = 12.5;
  config.width = 200, config.height = 150;
  config.keyframe_distance_m = 0.7;
  config.holdout_stride = 5;
  TempDir dir;
  Expected<SplatConfig> loaded = LoadSplatConfig(dir.Write("c.yaml", EmitSplatConfig(config)));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(EmitSplatConfig(*loaded), EmitSplatConfig(config));
  EXPECT_EQ(loaded->training.iterations, 123);
  EXPECT_EQ(loaded->width, 200);
  EXPECT_EQ(loaded->training.render.background.z(), 1.0f);
  EXPECT_EQ(loaded->training.max_gaussians, 12345u);
}

TEST(SplatConfig, OtherSectionsAreLeftToTheirReadersAndAFileWithoutTheSectionGivesTheDefaults) {
  TempDir dir;
  Expected<SplatConfig> loaded = LoadSplatConfig(dir.Write("c.yaml", "dataset:\n  format: auto\nlo: {}\n"));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(EmitSplatConfig(*loaded), EmitSplatConfig(SplatConfig{}));
}

using test::ExpectConfigError;

TEST(SplatConfig, BadFilesAreErrorsNamingFileKeyAndLine) {
  ExpectConfigError("splat:\n  iterations: 10\n  learning_rate: 1\n",
                    {"splat.learning_rate (line 3): unknown key"});
  ExpectConfigError("splat:\n  iterations: many\n",
                    {"splat.iterations (line 2): expected an integer, got 'many'"});
  ExpectConfigError("splat:\n  resolution: [320]\n", {"splat.resolution (line 2)", "[width, height]"});
  ExpectConfigError("splat:\n  background: [0, 0]\n", {"splat.background (line 2)"});
  ExpectConfigError("splats:\n  iterations: 1\n", {"unknown top-level key 'splats'"});
  ExpectConfigError("splat:\n  iterations: -3\n", {"splat.iterations: must be > 0, got -3"});
  ExpectConfigError("splat:\n  holdout_stride: 1\n", {"splat.holdout_stride: must be >= 2, got 1"});
  ExpectConfigError("splat:\n  resolution: [320, 0]\n", {"splat.resolution: must be two sizes"});
  ExpectConfigError("splat:\n  time_budget_s: -1\n", {"splat.time_budget_s: must be >= 0, got -1"});
}

TEST(SplatConfig, TheDefaultSizeHalvesTheCameraUntilItIsNarrowEnough) {
  int w = 0, h = 0;
  DefaultSize(640, 480, 320, w, h);
  EXPECT_EQ(w, 320);
  EXPECT_EQ(h, 240);
  DefaultSize(1241, 376, 320, w, h);  // KITTI: 1241 -> 620 -> 310
  EXPECT_EQ(w, 310);
  EXPECT_EQ(h, 94);
  DefaultSize(160, 120, 320, w, h);  // small cameras are kept as they are
  EXPECT_EQ(w, 160);
  EXPECT_EQ(h, 120);
}

TEST(SplatConfig, CoarseToFineStartsAtTheDefaultSizeAndDoublesEveryInterval) {
  SplatConfig config;
  config.coarse_to_fine_interval = 100;
  const auto size_at = [&](int width, int height, int iteration) {
    int w = 0, h = 0;
    CoarseToFineSize(config, width, height, iteration, w, h);
    return std::pair(w, h);
  };
  // KITTI at full size: 1242 x 375 -> 621 x 187 -> 310 x 93 (DefaultSize's halvings).
  EXPECT_EQ(size_at(1242, 375, 0), std::pair(310, 93));
  EXPECT_EQ(size_at(1242, 375, 99), std::pair(310, 93));
  EXPECT_EQ(size_at(1242, 375, 100), std::pair(621, 187));
  EXPECT_EQ(size_at(1242, 375, 199), std::pair(621, 187));
  EXPECT_EQ(size_at(1242, 375, 200), std::pair(1242, 375));
  EXPECT_EQ(size_at(1242, 375, 5000), std::pair(1242, 375));
  // A size within max_width trains as it is; so does every size with the interval 0.
  EXPECT_EQ(size_at(320, 240, 0), std::pair(320, 240));
  config.coarse_to_fine_interval = 0;
  EXPECT_EQ(size_at(1242, 375, 0), std::pair(1242, 375));
  ExpectConfigError("splat:\n  coarse_to_fine_interval: -5\n",
                    {"splat.coarse_to_fine_interval: must be >= 0, got -5"});
}

}  // namespace
}  // namespace uf::app
