// The splat stages of `ultrafusion run` end to end on a tiny simulated sequence: splats, metrics and EXR
// views written and trained again from an earlier run (`--from splat`), `render` of a run folder at given
// stamps placing the run's camera on its trajectory, and an unknown Vulkan device refused before the
// odometry runs. (The other stages: test_cli_pipeline.cpp.)
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "export/exr_view.h"
#include "export/splat_ply.h"
#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/trajectory_file.h"
#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"
#include "viewer/app/report/report_html.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::ReadBytes;
using testing::ReadText;
using testing::TempDir;

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
