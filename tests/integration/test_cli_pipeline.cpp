// `ultrafusion run` end to end as staged pipeline on a tiny simulated sequence: a versioned folder with
// runs/latest, every output file parsed back (trajectory accuracy against groundtruth.tum, PLY, LAS and
// glb structure, report.md and a self-contained report.html carrying the plots), the saved config repeating
// the run exactly, and a failing stage that keeps what was written and says why.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include "export/exr_view.h"
#include "export/splat_ply.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/trajectory_file.h"
#include "tests/support/cli_runner.h"
#include "tests/support/simulated_sequence.h"
#include "tests/support/temp_dir.h"
#include "viewer/app/report/report_html.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::ReadText;
using testing::TempDir;

std::vector<std::uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

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
class CliPipelineSplats : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    const auto sim = test::Ultrafusion("sim --scene urban --duration 4 --lidar spinning16 --config " +
                                       std::string(UF_SOURCE_DIR) +
                                       "/tests/integration/sim_small.yaml --out " + dir_->File("seq"));
    ASSERT_EQ(sim.code, 0) << sim.output;
  }
  static void TearDownTestSuite() { dir_.reset(); }
  // `run` on the sequence into dir/run, without the mesh, with the `splat:` section's keys `splat`.
  static test::CommandResult RunWithSplats(const TempDir& dir, const std::string& splat) {
    const std::string config = dir.Write("tiny.yaml", "splat:\n" + splat);
    return test::Ultrafusion("run " + dir_->File("seq") + " --config " + config + " --no-mesh --out " +
                             dir.File("run"));
  }
  static inline std::unique_ptr<TempDir> dir_;
};

TEST_F(CliPipelineSplats, SplatAndViewsStagesWriteSplatsMetricsAndExrViewsAndRunAgainFromSplat) {
  TempDir dir;
  const fs::path run = dir.path() / "run";
  const auto result = RunWithSplats(dir, "  iterations: 30\n  resolution: [80, 60]\n  comparisons: 2\n");
  ASSERT_EQ(result.code, 0) << result.output;
  for (const char* stage : {"map", "exports", "splat", "views", "accuracy"})
    EXPECT_TRUE(std::regex_search(result.output, std::regex(std::string("\\n  ") + stage + " +ok ")))
        << stage << "\n"
        << result.output;

  std::ifstream metrics_file(run / "metrics.json");
  const nlohmann::json metrics = nlohmann::json::parse(metrics_file);
  for (const char* key : {"psnr_test", "ssim_test", "iterations", "iterations_per_s", "gaussians", "device",
                          "views_train", "views_test", "psnr_train", "seconds", "resolution"})
    EXPECT_TRUE(metrics.contains(key)) << key;
  EXPECT_EQ(metrics["iterations"], 30);
  EXPECT_GT(metrics["psnr_test"].get<double>(), 8);
  EXPECT_LT(metrics["psnr_test"].get<double>(), 60);
  EXPECT_GT(metrics["ssim_test"].get<double>(), 0);
  EXPECT_GT(metrics["iterations_per_s"].get<double>(), 0);
  Expected<splat::GaussianModel> splats = exporting::ReadSplatPly((run / "splats.ply").string());
  ASSERT_TRUE(splats.ok()) << splats.error();
  EXPECT_EQ(splats->size(), metrics["gaussians"].get<std::size_t>());
  EXPECT_TRUE(fs::exists(run / "splats.glb"));

  // One EXR per held-out view at the camera's own size (sim_small.yaml: 160 x 120), with its PNG.
  int views = 0;
  for (const nlohmann::json& view : metrics["test_views"]) {
    const std::string stamp = std::to_string(view["stamp_ns"].get<std::int64_t>());
    Expected<exporting::ExrImage> exr = exporting::ReadExr((run / "views" / (stamp + ".exr")).string());
    ASSERT_TRUE(exr.ok()) << exr.error();
    EXPECT_EQ(exr->width, 160);
    EXPECT_EQ(exr->height, 120);
    for (const char* channel : {"R", "G", "B", "A", "Z"})
      EXPECT_TRUE(exr->channels.count(channel)) << channel;
    EXPECT_TRUE(fs::exists(run / "views" / (stamp + ".png")));
    ++views;
  }
  EXPECT_EQ(views, metrics["views_test"].get<int>());
  EXPECT_GE(views, 1);
  EXPECT_TRUE(fs::exists(run / "views/poses.tum"));
  EXPECT_TRUE(fs::exists(run / "views/camera.yaml"));

  const std::string report = ReadText((run / "report.md").string());
  for (const char* text : {"## Splats", "held-out PSNR [dB] (psnr_test)", "iterations per second",
                           "![splat training loss](plots/splat_loss.png)", "held-out views rendered"})
    EXPECT_NE(report.find(text), std::string::npos) << text << "\n" << report;
  const std::string html = ReadText((run / "report.html").string());
  // The loss plot and a held-out comparison are inlined in the HTML report.
  const std::string stamp = std::to_string(metrics["test_views"][0]["stamp_ns"].get<std::int64_t>());
  for (const fs::path& png : {run / "plots/splat_loss.png", run / "comparisons" / (stamp + "_compare.png")})
    EXPECT_NE(html.find(app::Base64(ReadBytes(png))), std::string::npos) << png << " is not inlined";
  EXPECT_NE(ReadText((run / "config.yaml").string()).find("splat:\n  iterations: 30\n"), std::string::npos);

  // --from splat trains again on the same folder's map and trajectory; the earlier stages are skipped and
  // their files left as they were.
  const std::vector<std::uint8_t> map_before = ReadBytes(run / "map.vdb");
  const std::string again_config =
      dir.Write("again.yaml", "splat:\n  iterations: 10\n  resolution: [80, 60]\n");
  const auto again = Ultrafusion("run " + dir_->File("seq") + " --config " + again_config +
                                 " --no-mesh --from splat --out " + run.string());
  ASSERT_EQ(again.code, 0) << again.output;
  for (const char* stage : {"dataset", "odometry", "map", "exports"})
    EXPECT_TRUE(std::regex_search(again.output, std::regex(std::string("\\n  ") + stage + " +skipped ")))
        << stage << "\n"
        << again.output;
  for (const char* stage : {"splat", "views"})
    EXPECT_TRUE(std::regex_search(again.output, std::regex(std::string("\\n  ") + stage + " +ok ")))
        << stage << "\n"
        << again.output;
  // The accuracy stage evaluates the same trajectory again: the same number of poses as the first run.
  const std::regex accuracy_line("\\n  accuracy +ok +([0-9]+) poses");
  std::smatch first_poses, again_poses;
  ASSERT_TRUE(std::regex_search(result.output, first_poses, accuracy_line)) << result.output;
  ASSERT_TRUE(std::regex_search(again.output, again_poses, accuracy_line)) << again.output;
  EXPECT_GT(std::stoi(first_poses[1]), 0);
  EXPECT_EQ(again_poses[1], first_poses[1]);
  std::ifstream again_metrics_file(run / "metrics.json");
  EXPECT_EQ(nlohmann::json::parse(again_metrics_file)["iterations"], 10);
  EXPECT_EQ(ReadBytes(run / "map.vdb"), map_before);
}

// A 4x4 matrix of run.json ("frames"), row-major rows.
SE3 RunJsonMatrix(const nlohmann::json& rows) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = rows.at(r).at(c).get<double>();
  return SE3::FromMatrix(m);
}

// The largest difference between two EXRs' channels `names`, over every pixel.
double WorstDifference(const exporting::ExrImage& a, const exporting::ExrImage& b,
                       std::initializer_list<const char*> names) {
  double worst = 0;
  for (const char* name : names) {
    const auto& x = a.channels.at(name);
    const auto& y = b.channels.at(name);
    EXPECT_EQ(x.size(), y.size()) << name;
    for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i)
      worst = std::max<double>(worst, std::abs(x[i] - y[i]));
  }
  return worst;
}

// `render RUN_DIR --stamps` renders the run's camera where the run's trajectory and the camera's extrinsic
// put it: at a held-out image's stamp, the view equals the one `render SPLATS --poses` gives at the pose
// composed here from trajectory.tum, run.json and the dataset's own calibration, and the views stage's view.
TEST_F(CliPipelineSplats, RenderingARunFolderAtStampsPlacesTheRunsCameraOnItsTrajectory) {
  TempDir dir;
  const fs::path run = dir.path() / "run";
  const auto result = RunWithSplats(dir, "  iterations: 20\n  resolution: [80, 60]\n  comparisons: 1\n");
  ASSERT_EQ(result.code, 0) << result.output;
  ASSERT_TRUE(fs::exists(run / "cameras.yaml"));
  std::ifstream metrics_file(run / "metrics.json");
  const Stamp stamp = nlohmann::json::parse(metrics_file)["test_views"][0]["stamp_ns"].get<Stamp>();

  // T_M_C = T_M_W * T_W_F(t) * T_F_B * T_B_C, from the run's files and the dataset's calibration.
  Expected<std::unique_ptr<DatasetReader>> dataset = OpenDataset(dir_->File("seq"));
  ASSERT_TRUE(dataset.ok()) << dataset.error();
  const StreamInfo* camera = nullptr;
  for (const StreamInfo& stream : (*dataset)->description().streams)
    if (stream.kind == SensorKind::kCamera && !camera) camera = &stream;
  ASSERT_TRUE(camera && camera->T_body_sensor && camera->camera_model);
  std::ifstream run_json_file(run / "run.json");
  const nlohmann::json frames = nlohmann::json::parse(run_json_file)["frames"];
  Expected<Trajectory> trajectory = ReadTrajectory((run / "trajectory.tum").string());
  ASSERT_TRUE(trajectory.ok()) << trajectory.error();
  const std::optional<SE3> T_world_frame = trajectory->PoseAt(stamp);
  ASSERT_TRUE(T_world_frame);
  const SE3 T_map_camera = RunJsonMatrix(frames["T_map_world"]) * *T_world_frame *
                           RunJsonMatrix(frames["T_output_body"]) * *camera->T_body_sensor;
  // The views stage placed the held-out image there too.
  Expected<Trajectory> views = ReadTrajectory((run / "views/poses.tum").string());
  ASSERT_TRUE(views.ok()) << views.error();
  const std::optional<SE3> view_pose = views->PoseAt(stamp);
  ASSERT_TRUE(view_pose);
  EXPECT_LT((view_pose->matrix() - T_map_camera.matrix()).cwiseAbs().maxCoeff(), 1e-8);

  // The old form at that pose, through the dataset's camera.
  const std::string poses = dir.File("pose.tum");
  ASSERT_TRUE(WriteTumTrajectory(poses, Trajectory{{stamp}, {T_map_camera}}).ok());
  ASSERT_TRUE(WriteCameraIntrinsicsFile(dir.File("camera.yaml"), *camera->camera_model).ok());
  const auto old_form =
      Ultrafusion("render " + (run / "splats.ply").string() + " --poses " + poses + " --camera " +
                  dir.File("camera.yaml") + " --out " + dir.File("old") + " --float");
  ASSERT_EQ(old_form.code, 0) << old_form.output;

  // The run folder at the stamp (and half way between the first two poses), with a comment and a blank line.
  const Stamp between = (trajectory->stamps[0] + trajectory->stamps[1]) / 2;
  const std::string stamps = dir.Write(
      "stamps.txt", "# a held-out image\n" + FormatSeconds(stamp) + "\n\n" + FormatSeconds(between) + "\n");
  const auto new_form = Ultrafusion("render " + run.string() + " --stamps " + stamps + " --out " +
                                    dir.File("new") + " --float --png");
  ASSERT_EQ(new_form.code, 0) << new_form.output;
  EXPECT_NE(new_form.output.find("render: 2 views of 160 x 120 px"), std::string::npos) << new_form.output;
  EXPECT_NE(new_form.output.find("camera " + camera->name + " of "), std::string::npos) << new_form.output;
  for (const Stamp t : {stamp, between})
    for (const char* extension : {".exr", ".png"})
      EXPECT_TRUE(fs::exists(dir.path() / "new" / (std::to_string(t) + extension))) << t << extension;
  const std::string name = std::to_string(stamp) + ".exr";
  Expected<exporting::ExrImage> rendered = exporting::ReadExr(dir.File("new/" + name));
  Expected<exporting::ExrImage> reference = exporting::ReadExr(dir.File("old/" + name));
  Expected<exporting::ExrImage> stage = exporting::ReadExr((run / "views" / name).string());
  ASSERT_TRUE(rendered.ok() && reference.ok() && stage.ok());
  // The same renderer at poses equal to the TUM file's nine decimals: float rounding only.
  EXPECT_LT(WorstDifference(*rendered, *reference, {"R", "G", "B", "A", "Z"}), 1e-4);
  // The views stage's half-float EXR: half precision (11 bits) on values up to 1.
  EXPECT_LT(WorstDifference(*rendered, *stage, {"R", "G", "B", "A"}), 2e-3);

  // Bad input: exit 1 with a message that names the problem.
  auto bad = Ultrafusion("render " + run.string() + " --stamps " + stamps +
                         " --camera no_such_camera --out " + dir.File("a"));
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("--camera no_such_camera: no such camera in"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("(cameras: " + camera->name + ")"), std::string::npos) << bad.output;
  const std::string late = dir.Write("late.txt", FormatSeconds(trajectory->stamps.back() + 1) + "\n");
  bad = Ultrafusion("render " + run.string() + " --stamps " + late + " --out " + dir.File("b"));
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("late.txt: stamp " + FormatSeconds(trajectory->stamps.back() + 1) + " s"),
            std::string::npos)
      << bad.output;
  EXPECT_NE(bad.output.find("is outside the span of " + (run / "trajectory.tum").string()), std::string::npos)
      << bad.output;
  const std::string words = dir.Write("words.txt", "1.5\nabc\n");
  bad = Ultrafusion("render " + run.string() + " --stamps " + words + " --out " + dir.File("c"));
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("words.txt:2: time (column 1) is not a time in seconds: 'abc'"),
            std::string::npos)
      << bad.output;
  fs::remove(run / "splats.ply");
  bad = Ultrafusion("render " + run.string() + " --stamps " + stamps + " --out " + dir.File("d"));
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("splats.ply: missing; the run trained no splats"), std::string::npos)
      << bad.output;
  // Options of the other form: a usage error.
  bad = Ultrafusion("render " + run.string() + " --poses " + poses + " --out " + dir.File("e"));
  EXPECT_EQ(bad.code, 2) << bad.output;
  EXPECT_NE(bad.output.find("a run folder renders at --stamps FILE"), std::string::npos) << bad.output;
  for (const char* folder : {"a", "b", "c", "d", "e"})
    EXPECT_FALSE(fs::exists(dir.path() / folder)) << folder;
}

// run --device: a device that is not there stops the run before anything is read or written.
TEST_F(CliPipelineSplats, RunWithAnUnknownDeviceFailsBeforeTheOdometry) {
  TempDir dir;
  const auto result =
      Ultrafusion("run " + dir_->File("seq") + " --device no-such-gpu --out " + dir.File("run"));
  EXPECT_EQ(result.code, 2) << result.output;
  EXPECT_NE(result.output.find("--device: Vulkan: no device matches 'no-such-gpu'; devices present: "),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir.File("run")));
}

}  // namespace
}  // namespace uf
