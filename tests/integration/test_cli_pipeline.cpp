// `ultrafusion run` end to end as staged pipeline on a tiny simulated sequence: a versioned folder with
// runs/latest, every output file parsed back (trajectory accuracy against groundtruth.tum, PLY, LAS and
// glb structure, report.md and a self-contained report.html carrying the plots), the saved config repeating
// the run exactly, and a failing stage that keeps what was written and says why. The splat stages:
// test_cli_pipeline_splats.cpp.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include "odometry/eval/evaluation.h"
#include "odometry/io/trajectory_file.h"
#include "tests/support/cli_runner.h"
#include "tests/support/simulated_sequence.h"
#include "tests/support/temp_dir.h"
#include "viewer/app/report/report_html.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::ReadBytes;
using testing::ReadText;
using testing::TempDir;

template <typename T>
T At(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  T value{};
  if (offset + sizeof(T) <= bytes.size()) std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

// A binary little-endian PLY: the header's vertex count and property sizes must account for the file's
// size exactly, and every x, y, z (the first three properties) must be finite. Returns the vertex count
// and (in stride_out) the bytes per vertex.
std::size_t CheckPly(const fs::path& path, std::size_t* stride_out = nullptr) {
  const std::vector<std::uint8_t> bytes = ReadBytes(path);
  const std::string text(bytes.begin(), bytes.end());
  const std::size_t end = text.find("end_header\n");
  EXPECT_EQ(text.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  if (end == std::string::npos) return 0;
  std::istringstream header(text.substr(0, end));
  std::size_t vertices = 0, stride = 0, other_elements = 0;
  bool in_vertex = false;
  for (std::string line; std::getline(header, line);) {
    std::istringstream words(line);
    std::string keyword, type, name;
    words >> keyword;
    if (keyword == "element") {
      words >> name;
      in_vertex = name == "vertex";
      if (in_vertex)
        words >> vertices;
      else
        ++other_elements;
    } else if (keyword == "property" && in_vertex) {
      words >> type;
      stride += type == "double"                                     ? 8
                : type == "float" || type == "int" || type == "uint" ? 4
                : type == "short" || type == "ushort"                ? 2
                                                                     : 1;
    }
  }
  EXPECT_EQ(other_elements, 0u);
  if (stride_out) *stride_out = stride;
  EXPECT_EQ(bytes.size(), end + 11 + vertices * stride) << path;
  for (std::size_t i = 0; i < vertices; i += 97)
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(At<float>(bytes, end + 11 + i * stride + 4 * k)));
  return vertices;
}

// The bounding box of a PLY's x, y, z (float, the first three properties), per axis min and max.
std::pair<Eigen::Vector3f, Eigen::Vector3f> PlyBounds(const fs::path& path, std::size_t stride) {
  const std::vector<std::uint8_t> bytes = ReadBytes(path);
  const std::string text(bytes.begin(), bytes.end());
  const std::size_t data = text.find("end_header\n") + 11;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = -lo;
  for (std::size_t at = data; at + stride <= bytes.size(); at += stride) {
    const Eigen::Vector3f p(At<float>(bytes, at), At<float>(bytes, at + 4), At<float>(bytes, at + 8));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

// LAS 1.4 (specification R15, Table 3): "LASF", a 375-byte header, the 64-bit point count at 247 and the
// record length at 105 accounting for the file size. Returns the point count.
std::uint64_t CheckLas(const fs::path& path) {
  const std::vector<std::uint8_t> b = ReadBytes(path);
  EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "LASF");
  EXPECT_EQ(At<std::uint8_t>(b, 24), 1);  // version 1.4
  EXPECT_EQ(At<std::uint8_t>(b, 25), 4);
  EXPECT_EQ(At<std::uint16_t>(b, 94), 375);
  const auto offset = At<std::uint32_t>(b, 96);
  const auto record = At<std::uint16_t>(b, 105);
  const auto count = At<std::uint64_t>(b, 247);
  EXPECT_EQ(b.size(), offset + std::uint64_t(record) * count) << path;
  return count;
}

// Every <img> of report.html carries the bytes of a plot file; returns how many there are.
int CheckInlinePlots(const std::string& html, const fs::path& folder) {
  std::set<std::string> inlined;
  const std::string key = "src=\"data:image/png;base64,";
  for (std::size_t at = html.find(key); at != std::string::npos; at = html.find(key, at + 1))
    inlined.insert(html.substr(at + key.size(), html.find('"', at + key.size()) - at - key.size()));
  int plots = 0;
  for (const fs::directory_entry& png : fs::directory_iterator(folder / "plots")) {
    ++plots;
    EXPECT_TRUE(inlined.count(app::Base64(ReadBytes(png.path())))) << png.path() << " is not inlined";
  }
  EXPECT_EQ(inlined.size(), static_cast<std::size_t>(plots));
  return plots;
}

// SE3-aligned ATE of trajectory.tum against the simulator's ground truth.
double Ate(const fs::path& ground_truth, const fs::path& estimate) {
  Expected<Trajectory> reference = ReadTrajectory(ground_truth.string());
  Expected<Trajectory> estimated = ReadTrajectory(estimate.string());
  EXPECT_TRUE(reference.ok() && estimated.ok());
  if (!reference.ok() || !estimated.ok()) return 1e9;
  Expected<EvalResult> result = Evaluate(*reference, *estimated, EvalOptions{});
  EXPECT_TRUE(result.ok());
  return result.ok() ? result->ape.rmse : 1e9;
}

// `ultrafusion ARGUMENTS` run from `folder` (the versioned output then goes under folder/runs).
test::CommandResult UltrafusionIn(const fs::path& folder, const std::string& arguments) {
  return test::Ultrafusion(arguments, true, "cd '" + folder.string() + "' &&");
}

class CliPipeline : public testing::SimulatedSequenceTest {};

TEST_F(CliPipeline, EveryStageRunsIntoAVersionedFolderAndEveryOutputParses) {
  TempDir work;
  const auto result = UltrafusionIn(work.path(), "run " + Sequence());
  ASSERT_EQ(result.code, 0) << result.output;
  // runs/<UTC YYYYmmdd-HHMMSS>/ and runs/latest pointing at it.
  const fs::path runs = work.path() / "runs";
  ASSERT_TRUE(fs::is_symlink(runs / "latest")) << result.output;
  const std::string name = fs::read_symlink(runs / "latest").string();
  EXPECT_TRUE(std::regex_match(name, std::regex("[0-9]{8}-[0-9]{6}(-[0-9]+)?"))) << name;
  const fs::path run = runs / name;
  ASSERT_TRUE(fs::is_directory(run));

  // The summary table: every stage ran.
  for (const char* stage : {"dataset", "odometry", "map", "exports", "accuracy"})
    EXPECT_TRUE(std::regex_search(result.output, std::regex(std::string("\\n  ") + stage + " +ok ")))
        << stage << "\n"
        << result.output;
  for (const char* file : {"trajectory.tum", "trajectory_kitti.txt", "timing.json", "config.yaml",
                           "report.md", "report.html", "map.vdb", "map.ply", "map.las", "map.glb",
                           "georef.json", "plots/timing_per_scan.png", "plots/ape_top_view.png"})
    EXPECT_TRUE(fs::exists(run / file)) << file;

  // LIO in the IMU frame, the frame of the ground truth: centimetres when it works, metres when lost.
  EXPECT_LT(Ate(fs::path(Sequence()) / "groundtruth.tum", run / "trajectory.tum"), 0.1);
  const std::size_t ply_points = CheckPly(run / "map.ply");
  EXPECT_GT(ply_points, 1000u);
  EXPECT_EQ(CheckLas(run / "map.las"), ply_points);  // the same map points in both
  tinygltf::TinyGLTF loader;
  tinygltf::Model glb;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&glb, &error, &warning, (run / "map.glb").string())) << error;
  // The point cloud: a POINTS primitive with one position per map point (the mesh is another primitive).
  std::size_t glb_points = 0;
  for (const tinygltf::Mesh& mesh : glb.meshes)
    for (const tinygltf::Primitive& primitive : mesh.primitives)
      if (primitive.mode == TINYGLTF_MODE_POINTS)
        glb_points += glb.accessors.at(primitive.attributes.at("POSITION")).count;
  EXPECT_EQ(glb_points, ply_points);

  const std::string report = ReadText((run / "report.md").string());
  for (const char* section : {"## Stages", "## Dataset (as `ultrafusion info` prints it)", "## Map",
                              "![time per scan](plots/timing_per_scan.png)", "## Warnings", "ATE (APE"})
    EXPECT_NE(report.find(section), std::string::npos) << section << "\n" << report;
  EXPECT_EQ(report.find("Run failed"), std::string::npos);
  const std::string html = ReadText((run / "report.html").string());
  EXPECT_GE(CheckInlinePlots(html, run), 4);  // the timing plot and the three accuracy plots
  EXPECT_EQ(html.find("http"), std::string::npos);

  // A second run in the same folder gets a folder of its own, and latest moves to it.
  const auto again = UltrafusionIn(work.path(), "run " + Sequence() + " --mode lo --no-map");
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_NE(fs::read_symlink(runs / "latest").string(), name);
  EXPECT_TRUE(fs::exists(run / "map.ply"));
}

TEST_F(CliPipeline, TheSavedConfigRepeatsTheRunExactly) {
  TempDir dir;
  // The solver's wall-clock budget per scan (lo.max_solver_time_s, 0.04 s) makes the result depend on the
  // machine's load; with a budget it never reaches, the run is a function of data and config alone.
  const std::string budget = dir.Write("budget.yaml", "lo:\n  max_solver_time_s: 1000\n");
  const std::string first = dir.File("first");
  const auto result = Ultrafusion("run " + Sequence() + " --config " + budget +
                                  " --mode lo --no-map --map-voxel 0.1 --out " + first);
  ASSERT_EQ(result.code, 0) << result.output;
  // config.yaml states the command that repeats the run: take it as it is written there.
  const std::string config = ReadText(first + "/config.yaml");
  std::smatch repeat;
  ASSERT_TRUE(std::regex_search(config, repeat, std::regex("#   ultrafusion run (.*) --out NEW_FOLDER\n")))
      << config;
  std::string arguments = repeat[1].str();
  arguments.replace(arguments.find("--config config.yaml"), 20, "--config " + first + "/config.yaml");
  const std::string second = dir.File("second");
  const auto repeated = Ultrafusion("run " + arguments + " --out " + second);
  ASSERT_EQ(repeated.code, 0) << repeated.output;
  EXPECT_EQ(ReadText(second + "/trajectory.tum"), ReadText(first + "/trajectory.tum"));
  EXPECT_EQ(ReadText(second + "/config.yaml"), config);
}

TEST_F(CliPipeline, AFailingStageStopsTheRunKeepsWhatWasWrittenAndSaysWhy) {
  TempDir dir;
  // The sequence with its LiDAR file cut in the middle of a scan: the data is damaged.
  const fs::path damaged = dir.path() / "damaged";
  fs::copy(Sequence(), damaged, fs::copy_options::recursive);
  const fs::path lidar = damaged / "lidar.bin";
  ASSERT_TRUE(fs::exists(lidar));
  fs::resize_file(lidar, fs::file_size(lidar) / 2 + 3);
  const std::string out = dir.File("out");
  const auto result = Ultrafusion("run " + damaged.string() + " --out " + out);
  EXPECT_EQ(result.code, 1) << result.output;
  EXPECT_NE(result.output.find("stage failed"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(out + "/config.yaml"));
  const std::string report = ReadText(out + "/report.md");
  EXPECT_NE(report.find("**Run failed** in the "), std::string::npos) << report;
  EXPECT_NE(report.find("lidar.bin"), std::string::npos) << report;  // the message names the file
  EXPECT_NE(report.find("not run"), std::string::npos) << report;
  EXPECT_TRUE(fs::exists(out + "/report.html"));
}

TEST_F(CliPipeline, FromMapRemakesTheMapFromTheEarlierTrajectory) {
  TempDir dir;
  const std::string run = dir.File("run");
  const auto first = Ultrafusion("run " + Sequence() + " --mode lo --no-mesh --out " + run);
  ASSERT_EQ(first.code, 0) << first.output;
  const std::string trajectory = ReadText(run + "/trajectory.tum");
  std::size_t stride = 0;
  const std::size_t points = CheckPly(run + "/map.ply", &stride);
  ASSERT_GE(stride, 12u);
  const auto bounds = PlyBounds(run + "/map.ply", stride);
  fs::remove(run + "/map.ply");

  // The map again, from trajectory.tum and the scans deskewed with it: no odometry runs.
  const auto again = Ultrafusion("run " + Sequence() + " --mode lo --no-mesh --from map --out " + run);
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_TRUE(std::regex_search(again.output, std::regex("\\n  odometry +skipped ")));
  EXPECT_TRUE(std::regex_search(again.output, std::regex("\\n  map +ok ")));
  EXPECT_EQ(ReadText(run + "/trajectory.tum"), trajectory);
  // The same scans in the same places: the odometry deskews with its own state, this stage interpolates
  // the keyframe poses, so the maps agree to a few percent of their points and centimetres of their extent.
  const std::size_t remade = CheckPly(run + "/map.ply");
  EXPECT_NEAR(static_cast<double>(remade), static_cast<double>(points), 0.05 * points);
  const auto remade_bounds = PlyBounds(run + "/map.ply", stride);
  EXPECT_LT((remade_bounds.first - bounds.first).cwiseAbs().maxCoeff(), 0.2);
  EXPECT_LT((remade_bounds.second - bounds.second).cwiseAbs().maxCoeff(), 0.2);
  EXPECT_NE(ReadText(run + "/report.md").find("--from map"), std::string::npos);

  // Without an earlier run in --out there is nothing to start from.
  const auto nothing = Ultrafusion("run " + Sequence() + " --from map --out " + dir.File("empty"));
  EXPECT_EQ(nothing.code, 2) << nothing.output;
  EXPECT_NE(nothing.output.find("trajectory.tum"), std::string::npos) << nothing.output;
}

// The same tiny sequence with its camera: the splat and views stages run with a budget of a few tens of
// iterations at 80 x 60, and their outputs parse.

}  // namespace
}  // namespace uf
