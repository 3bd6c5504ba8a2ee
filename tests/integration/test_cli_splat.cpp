// `ultrafusion splat RUN_DIR` as a user runs it, on a tiny simulated run (4 s of the urban scene, a 160 x 120
// camera): every output parsed back, the images placed where the simulator's ground truth puts them, and
// bad input (no images, images without a camera model, a trajectory with NaN, missing files, a map without
// colour, unknown configuration keys): clear messages, the right exit codes, nothing under a final name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>

#include "export/exr_view.h"
#include "export/splat_gltf.h"
#include "export/splat_ply.h"
#include "odometry/io/image_decode.h"
#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::ReadText;
using testing::TempDir;

// Tiny and quick: a few tens of iterations at 80 x 60.
constexpr const char* kTiny = " --iterations 20 --resolution 80 60";

class CliSplat : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    const std::string sim = "sim --scene urban --duration 4 --lidar spinning16 --config " +
                            std::string(UF_SOURCE_DIR) + "/tests/integration/sim_small.yaml";
    for (const auto& [folder, extra] :
         {std::pair<std::string, std::string>{"seq", ""}, {"seq_nocam", " --no-camera"}}) {
      const auto made = Ultrafusion(sim + extra + " --out " + dir_->File(folder));
      ASSERT_EQ(made.code, 0) << made.output;
      const auto run = Ultrafusion("run " + dir_->File(folder) + " --mode lio --no-splat --no-mesh --out " +
                                   dir_->File("run_" + folder));
      ASSERT_EQ(run.code, 0) << run.output;
    }
  }
  static void TearDownTestSuite() { dir_.reset(); }

  // A copy of an earlier run's folder to work in.
  static std::string CopyRun(const TempDir& work, const std::string& run = "run_seq") {
    const fs::path copy = work.path() / run;
    fs::copy(dir_->File(run), copy, fs::copy_options::recursive);
    return copy.string();
  }
  static std::string File(const std::string& name) { return dir_->File(name); }

  static inline std::unique_ptr<TempDir> dir_;
};

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void ExpectNoOutputs(const std::string& run) {
  for (const char* file : {"splats.ply", "splats.glb", "metrics.json", "comparisons"})
    EXPECT_FALSE(fs::exists(fs::path(run) / file)) << file;
}

TEST_F(CliSplat, TrainsOnTheRunAndEveryOutputParses) {
  TempDir work;
  const std::string run = CopyRun(work);
  const auto result = Ultrafusion("splat " + run + kTiny);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("splat: 20 iterations"), std::string::npos) << result.output;

  const nlohmann::json m = ReadJson(fs::path(run) / "metrics.json");
  for (const char* key :
       {"psnr_test", "ssim_test", "psnr_test_initial", "psnr_train", "iterations", "iterations_per_s",
        "gaussians", "device", "views_train", "views_test", "seconds", "resolution", "images", "test_views"})
    EXPECT_TRUE(m.contains(key)) << key;
  EXPECT_EQ(m["iterations"], 20);
  EXPECT_GT(m["iterations_per_s"].get<double>(), 0);
  EXPECT_GT(m["psnr_test"].get<double>(), 8);
  EXPECT_LT(m["psnr_test"].get<double>(), 60);
  EXPECT_GT(m["ssim_test"].get<double>(), 0);
  EXPECT_LE(m["ssim_test"].get<double>(), 1);
  EXPECT_EQ(m["resolution"], nlohmann::json({80, 60}));
  EXPECT_GE(m["views_test"].get<int>(), 1);
  EXPECT_GE(m["views_train"].get<int>(), 4);
  EXPECT_EQ(m["images"], 41);  // 4 s at 10 Hz, both ends
  EXPECT_FALSE(m["device"].get<std::string>().empty());
  // Where the time went: every device stage and the host's rest, which add up to the training's seconds.
  const nlohmann::json& stages = m["stage_seconds"];
  for (const char* stage :
       {"project", "sort", "rasterize", "loss gradient", "rasterize backward", "adam", "host"})
    EXPECT_TRUE(stages.contains(stage)) << stage;
  double stage_sum = 0;
  for (const auto& [stage, seconds] : stages.items()) {
    EXPECT_GE(seconds.get<double>(), 0) << stage;
    stage_sum += seconds.get<double>();
  }
  EXPECT_NEAR(stage_sum, m["seconds"].get<double>(), 1e-6 + 1e-3 * m["seconds"].get<double>());
  EXPECT_NE(result.output.find("time per iteration: project"), std::string::npos) << result.output;

  Expected<splat::GaussianModel> ply = exporting::ReadSplatPly(run + "/splats.ply");
  ASSERT_TRUE(ply.ok()) << ply.error();
  EXPECT_EQ(ply->size(), m["gaussians"].get<std::size_t>());
  EXPECT_GT(ply->size(), 1000u);
  Expected<splat::GaussianModel> glb = exporting::ReadSplatGltf(run + "/splats.glb");
  ASSERT_TRUE(glb.ok()) << glb.error();
  EXPECT_EQ(glb->size(), ply->size());
  // Comparisons for the held-out views, named by stamp.
  const std::string stamp = std::to_string(m["test_views"][0]["stamp_ns"].get<std::int64_t>());
  for (const char* suffix : {"_render.png", "_real.png", "_compare.png"})
    EXPECT_TRUE(fs::exists(run + "/comparisons/" + stamp + suffix)) << suffix;
  Expected<exporting::ExrImage> exr = exporting::ReadExr(run + "/comparisons/" + stamp + ".exr");
  ASSERT_TRUE(exr.ok()) << exr.error();
  EXPECT_EQ(exr->width, 80);
  EXPECT_EQ(exr->height, 60);
  EXPECT_TRUE(fs::exists(run + "/plots/splat_loss.png"));
}

// Coarse to fine: 160 x 120 with max_width 40 trains at 40 x 30, then 80 x 60 every 5 iterations, then the
// full size; metrics.json and the summary account for the steps at each size, the scores are at full size.
TEST_F(CliSplat, CoarseToFineTrainsAtEachSizeInTurnAndReportsIt) {
  TempDir work;
  const std::string run = CopyRun(work);
  const std::string config =
      work.Write("splat.yaml", "splat:\n  max_width: 40\n  coarse_to_fine_interval: 5\n");
  const auto result =
      Ultrafusion("splat " + run + " --iterations 20 --resolution 160 120 --config " + config);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_TRUE(std::regex_search(
      result.output, std::regex("coarse to fine: 40 x 30 px 5 iterations in [0-9.]+ s \\([0-9.]+ it/s\\), "
                                "80 x 60 px 5 iterations .*, 160 x 120 px 10 iterations")))
      << result.output;
  const nlohmann::json m = ReadJson(fs::path(run) / "metrics.json");
  const nlohmann::json& sizes = m["sizes"];
  ASSERT_EQ(sizes.size(), 3u) << sizes;
  const std::vector<std::pair<int, int>> expected = {{40, 30}, {80, 60}, {160, 120}};
  double seconds = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(sizes[i]["resolution"], nlohmann::json({expected[i].first, expected[i].second})) << i;
    EXPECT_EQ(sizes[i]["iterations"], i < 2 ? 5 : 10) << i;
    seconds += sizes[i]["seconds"].get<double>();
  }
  EXPECT_NEAR(seconds, m["seconds"].get<double>(), 1e-6);
  EXPECT_EQ(m["resolution"], nlohmann::json({160, 120}));
  Expected<exporting::ExrImage> exr = exporting::ReadExr(
      run + "/comparisons/" + std::to_string(m["test_views"][0]["stamp_ns"].get<std::int64_t>()) + ".exr");
  ASSERT_TRUE(exr.ok()) << exr.error();
  EXPECT_EQ(exr->width, 160);
  // A size within max_width (80 x 60 of the default 320): one size.
  const auto plain = Ultrafusion("splat " + run + kTiny);
  ASSERT_EQ(plain.code, 0) << plain.output;
  EXPECT_EQ(plain.output.find("coarse to fine"), std::string::npos) << plain.output;
  EXPECT_EQ(ReadJson(fs::path(run) / "metrics.json")["sizes"].size(), 1u);
}

// The seeded splats (the coloured map, one iteration in) rendered at the held-out images' poses: with the
// run's trajectory and with the simulator's ground truth the images line up alike; moved 0.5 m sideways they
// do not. SSIM, not PSNR: the sky, which the map has no points for, dominates the squared error alike.
TEST_F(CliSplat, ImagesArePlacedWhereTheGroundTruthPutsThem) {
  TempDir work;
  const std::string run = CopyRun(work);
  auto seeded_ssim = [&](const std::string& poses) {
    const auto result = Ultrafusion("splat " + run + " --iterations 1 --resolution 80 60" +
                                    (poses.empty() ? "" : " --poses " + poses));
    EXPECT_EQ(result.code, 0) << result.output;
    return ReadJson(fs::path(run) / "metrics.json")["ssim_test"].get<double>();
  };
  const double estimated = seeded_ssim("");
  const std::string truth = File("seq") + "/groundtruth.tum";
  const double ground_truth = seeded_ssim(truth);
  // The ground truth shifted 0.5 m to the left of the car (+y of the IMU frame).
  std::ifstream in(truth);
  std::ofstream shifted(work.File("shifted.tum"));
  for (std::string line; std::getline(in, line);) {
    double t, x, y, z, qx, qy, qz, qw;
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &t, &x, &y, &z, &qx, &qy, &qz, &qw) !=
        8) {
      shifted << line << "\n";
      continue;
    }
    const Eigen::Vector3d left = Eigen::Quaterniond(qw, qx, qy, qz) * Eigen::Vector3d(0, 0.5, 0);
    const std::string stamp = line.substr(0, line.find(' '));
    shifted << stamp << " " << x + left.x() << " " << y + left.y() << " " << z + left.z() << " " << qx << " "
            << qy << " " << qz << " " << qw << "\n";
  }
  shifted.close();
  const double moved = seeded_ssim(work.File("shifted.tum"));
  EXPECT_NEAR(ground_truth, estimated, 0.03);
  EXPECT_LT(moved, ground_truth - 0.03) << estimated << " " << ground_truth << " " << moved;
}

TEST_F(CliSplat, ARunWithoutImagesTrainsNothingAndSaysWhy) {
  TempDir work;
  const std::string run = CopyRun(work, "run_seq_nocam");
  const auto result = Ultrafusion("splat " + run + kTiny);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("no camera stream, so there are no images"), std::string::npos)
      << result.output;
  ExpectNoOutputs(run);
}

TEST_F(CliSplat, ImagesWithoutACameraModelAreAnError) {
  TempDir work;
  // The sequence with its camera's calibration block removed from dataset.yaml.
  const fs::path seq = work.path() / "seq";
  fs::copy(File("seq"), seq, fs::copy_options::recursive);
  const std::string yaml = ReadText((seq / "dataset.yaml").string());
  std::ofstream((seq / "dataset.yaml").string())
      << std::regex_replace(yaml, std::regex("    calibration:\n(      .*\n)+"), "");
  const std::string run = CopyRun(work);
  const std::string run_json = ReadText(run + "/run.json");
  std::ofstream(run + "/run.json") << std::regex_replace(run_json, std::regex("\"dataset\": \"[^\"]*\""),
                                                         "\"dataset\": \"" + seq.string() + "\"");
  const auto result = Ultrafusion("splat " + run + kTiny);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("camera cam0 has no intrinsics"), std::string::npos) << result.output;
  ExpectNoOutputs(run);
}

TEST_F(CliSplat, ATrajectoryWithNanIsAnErrorNamingFileAndLine) {
  TempDir work;
  const std::string run = CopyRun(work);
  std::string text = ReadText(run + "/trajectory.tum");
  // Line 3 (the header is line 1): its x becomes nan.
  std::size_t at = 0;
  for (int line = 1; line < 3; ++line) at = text.find('\n', at) + 1;
  const std::size_t x = text.find(' ', at) + 1;
  text.replace(x, text.find(' ', x) - x, "nan");
  std::ofstream(run + "/trajectory.tum") << text;
  const auto result = Ultrafusion("splat " + run + kTiny);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("trajectory.tum:3: "), std::string::npos) << result.output;  // file:line
  ExpectNoOutputs(run);
}

TEST_F(CliSplat, MissingRunFilesAreErrorsNamingThem) {
  TempDir work;
  const std::string run = CopyRun(work);
  fs::remove(run + "/map.vdb");
  auto result = Ultrafusion("splat " + run + kTiny);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("map.vdb: missing"), std::string::npos) << result.output;
  fs::remove(run + "/trajectory.tum");
  result = Ultrafusion("splat " + run + kTiny);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("trajectory.tum: missing"), std::string::npos) << result.output;
  fs::remove(run + "/run.json");
  result = Ultrafusion("splat " + run + kTiny);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("re-run `ultrafusion run`"), std::string::npos) << result.output;
  ExpectNoOutputs(run);
}

TEST_F(CliSplat, AMapWithoutColourIsSeededGreyWithAWarning) {
  TempDir work;
  // The run without a camera made an uncoloured map; its run.json now names the same sequence with images.
  const std::string run = CopyRun(work, "run_seq_nocam");
  const std::string run_json = ReadText(run + "/run.json");
  std::ofstream(run + "/run.json") << std::regex_replace(run_json, std::regex("\"dataset\": \"[^\"]*\""),
                                                         "\"dataset\": \"" + File("seq") + "\"");
  const auto result = Ultrafusion("splat " + run + " --iterations 5 --resolution 80 60");
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_TRUE(
      std::regex_search(result.output, std::regex("warning: [0-9]+ of [0-9]+ map points have no colour")))
      << result.output;
  const nlohmann::json m = ReadJson(fs::path(run) / "metrics.json");
  EXPECT_EQ(m["uncoloured_seeds"], m["map_seeds"]);
  EXPECT_EQ(m["gaussians_initial"].get<int>(),
            m["map_seeds"].get<int>() + m["feature_seeds"].get<int>() + m["sky_gaussians"].get<int>());
  EXPECT_EQ(m["sky_gaussians"], 30000);
}

// A PNG mask of width x height whose bottom `black_rows` rows are black (masked).
std::string WriteMask(const TempDir& work, int width, int height, int black_rows) {
  Image mask{width, height, 1, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height, 255)};
  std::fill(mask.pixels.end() - static_cast<std::ptrdiff_t>(black_rows) * width, mask.pixels.end(), 0);
  const Expected<std::vector<std::uint8_t>> png = EncodePng(mask, "mask");
  EXPECT_TRUE(png.ok()) << png.error();
  const std::string file = work.File("mask.png");
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(png->data()), static_cast<std::streamsize>(png->size()));
  return file;
}

TEST_F(CliSplat, AMaskImageLeavesItsBlackPixelsOutAndAWrongOneIsAnError) {
  TempDir work;
  const std::string run = CopyRun(work);
  // The camera is 160 x 120; its bottom quarter black: at 80 x 60, the bottom 15 rows.
  const std::string config =
      work.Write("splat.yaml", "splat:\n  mask_image: " + WriteMask(work, 160, 120, 30) + "\n");
  auto result = Ultrafusion("splat " + run + kTiny + " --config " + config);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_EQ(ReadJson(fs::path(run) / "metrics.json")["masked_pixels"], 80 * 15);

  TempDir fresh;  // a run folder that has no splat outputs yet
  const std::string other = CopyRun(fresh);
  const std::string wrong = WriteMask(work, 100, 120, 30);
  const std::string wrong_config = work.Write("wrong.yaml", "splat:\n  mask_image: " + wrong + "\n");
  result = Ultrafusion("splat " + other + kTiny + " --config " + wrong_config);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find(wrong + " is 100 x 120 px, the camera 160 x 120"), std::string::npos)
      << result.output;
  ExpectNoOutputs(other);
  const std::string missing =
      work.Write("missing.yaml", "splat:\n  mask_image: " + work.File("none.png") + "\n");
  result = Ultrafusion("splat " + other + kTiny + " --config " + missing);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("splat.mask_image: " + work.File("none.png") + ": cannot open"),
            std::string::npos)
      << result.output;
  ExpectNoOutputs(other);
}

TEST_F(CliSplat, UnknownConfigurationKeysAreUsageErrors) {
  TempDir work;
  const std::string run = CopyRun(work);
  const std::string config = work.Write("splat.yaml", "splat:\n  iterations: 10\n  itterations: 20\n");
  const auto result = Ultrafusion("splat " + run + " --config " + config);
  EXPECT_EQ(result.code, 2) << result.output;
  EXPECT_NE(result.output.find(config + ": splat.itterations (line 3): unknown key"), std::string::npos)
      << result.output;
  ExpectNoOutputs(run);
}

}  // namespace
}  // namespace uf
