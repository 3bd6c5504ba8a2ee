// `ultrafusion track` as a user runs it: the visual front end over a simulated camera, its files, and bad
// input (a frame that does not decode, a camera that is not there, a mask of the wrong size).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odometry/io/image_decode.h"
#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::TempDir;

// The rows of tracks.csv after its header, each split at commas.
std::vector<std::vector<std::string>> CsvRows(const std::string& path) {
  std::istringstream in(testing::ReadText(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream cell_in(line);
    for (std::string cell; std::getline(cell_in, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

class CliTrack : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const auto sim = Ultrafusion("sim --scene urban --duration 3 --seed 4 --no-gnss --no-wheel --out " +
                                 dir_->File("seq"));
    ASSERT_EQ(sim.code, 0) << sim.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string Seq() { return dir_->File("seq"); }
  static TempDir* dir_;
};
TempDir* CliTrack::dir_ = nullptr;

TEST_F(CliTrack, TracksTheSimulatedCameraAndWritesItsFiles) {
  const std::string out = dir_->File("track");
  const auto result = Ultrafusion("track " + Seq() + " --overlay-every 10 --out " + out);
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("track: cam0 (640 x 480): 31 frames tracked"), std::string::npos)
      << result.output;
  const auto rows = CsvRows(out + "/tracks.csv");
  ASSERT_EQ(rows.size(), 31u);
  int features = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 20u);
    features += std::stoi(row[1]);
    EXPECT_EQ(row[17], "");      // no stereo
    EXPECT_EQ(row[19], "\"\"");  // no poor frame
  }
  EXPECT_EQ(rows[0][14], "1");      // the first frame is a keyframe
  EXPECT_EQ(rows[0][16], "1.000");  // and has no tracks: degenerate
  EXPECT_LT(std::stod(rows[10][16]), 0.5);
  EXPECT_GT(features / 31, 120);
  for (const char* plot : {"track_features.png", "track_ratio.png", "track_degeneracy.png"})
    EXPECT_TRUE(fs::exists(out + "/plots/" + plot)) << plot;
  int overlays = 0;
  for (const auto& entry : fs::directory_iterator(out + "/plots"))
    overlays += entry.path().filename().string().starts_with("tracks_");
  EXPECT_EQ(overlays, 4);  // frames 0, 10, 20, 30
  EXPECT_TRUE(fs::exists(out + "/plots/tracks_" + rows[10][0] + ".png"));
}

// --smoothing reaches the front end (its effect on the tracks: test_feature_tracker.cpp), within [0, 5] px.
TEST_F(CliTrack, SmoothingReachesTheFrontEndAndIsRangeChecked) {
  const auto counts = [this](const std::string& smoothing) {
    const std::string out = dir_->File("smoothing" + smoothing);
    const auto result =
        Ultrafusion("track " + Seq() + " --overlay-every 0 --smoothing " + smoothing + " --out " + out);
    EXPECT_EQ(result.code, 0) << result.output;
    std::vector<std::string> column;  // tracked, detected and the losses of every frame
    for (const auto& row : CsvRows(out + "/tracks.csv"))
      for (int i = 2; i <= 7; ++i) column.push_back(row.at(i));
    return column;
  };
  EXPECT_EQ(counts("0"), counts("0.0"));
  EXPECT_NE(counts("0"), counts("0.8"));
  const auto result = Ultrafusion("track " + Seq() + " --smoothing 9");
  EXPECT_EQ(result.code, 2) << result.output;
  EXPECT_NE(result.output.find("--smoothing"), std::string::npos) << result.output;
}

TEST_F(CliTrack, AFrameThatDoesNotDecodeIsSkippedWithAWarning) {
  TempDir copy;
  fs::copy(Seq(), copy.File("seq"), fs::copy_options::recursive);
  const fs::path broken = fs::path(copy.File("seq")) / "cam0" / "1700000001000000000.png";
  ASSERT_TRUE(fs::exists(broken));
  fs::resize_file(broken, 100);  // a truncated PNG
  const auto result = Ultrafusion("track " + copy.File("seq"));
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("30 frames tracked, 1 skipped (1 undecodable, 0 refused)"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("frame at 1700000001.000000 s: "), std::string::npos) << result.output;
}

TEST_F(CliTrack, BadCameraOrMaskIsAnErrorNamingIt) {
  auto result = Ultrafusion("track " + Seq() + " --camera cam7");
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("track needs a camera stream named cam7; the dataset has"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("cam0"), std::string::npos) << result.output;

  const std::string mask = dir_->File("mask.png");
  {
    auto png = EncodePng(Image{2, 1, 1, {0, 255}}, "mask");  // a valid image of the wrong size
    ASSERT_TRUE(png);
    std::ofstream(mask, std::ios::binary).write(reinterpret_cast<const char*>(png->data()), png->size());
  }
  result = Ultrafusion("track " + Seq() + " --mask " + mask);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("--mask: " + mask + " is 2 x 1 px, the camera 640 x 480"), std::string::npos)
      << result.output;

  TempDir no_camera;
  ASSERT_EQ(Ultrafusion("sim --scene urban --duration 2 --no-camera --no-gnss --no-wheel --out " +
                        no_camera.File("seq"))
                .code,
            0);
  result = Ultrafusion("track " + no_camera.File("seq"));
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("track needs a camera stream; the dataset has"), std::string::npos)
      << result.output;
}

// The real EuRoC stereo pair: every cam0 frame finds its cam1 partner, and the matches fit the calibrated
// extrinsic (an epipolar distance of a fraction of a pixel).
TEST(CliTrackStereo, EurocPairsMatchAndFitTheirExtrinsic) {
  const std::string shared = testing::SharedData();
  const fs::path folder = fs::path(shared) / "euroc-v101-micro";
  if (shared.empty() || !fs::exists(folder)) GTEST_SKIP() << "no recorded data at " << folder;
  TempDir dir;
  const auto result =
      Ultrafusion("track " + folder.string() + " --stereo mav0/cam1/data.csv --out " + dir.File("t"));
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("stereo mav0/cam1/data.csv: 16 pairs"), std::string::npos) << result.output;
  const auto rows = CsvRows(dir.File("t") + "/tracks.csv");
  ASSERT_EQ(rows.size(), 16u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 20u);
    EXPECT_GT(std::stoi(row[17]), 30);
    EXPECT_LT(std::stod(row[18]), 0.5);
  }
  auto same = Ultrafusion("track " + folder.string() + " --stereo mav0/cam0/data.csv");
  EXPECT_EQ(same.code, 1) << same.output;
  EXPECT_NE(same.output.find("the tracked camera itself"), std::string::npos) << same.output;
}

TEST_F(CliTrack, AStereoCameraThatIsNotThereIsAnError) {
  const auto result = Ultrafusion("track " + Seq() + " --stereo cam1");
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("track needs a camera stream named cam1"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace uf
