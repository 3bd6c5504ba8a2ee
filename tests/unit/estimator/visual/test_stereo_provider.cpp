// The camera's part of the window with a stereo rig (providers/visual_provider.h, SetStereo) on frames of
// the simulated urban drive with the cameras' true poses as the nodes: landmarks start with the pair's
// depth, which the scene's ray caster confirms, and the right camera's factors reproject at the truth; right
// frames that do not fit leave the left frame alone, with a warning; a rig without a baseline is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "odometry/estimator/providers/visual_provider.h"
#include "tests/unit/estimator/visual/simulated_camera.h"

namespace uf::estimator {
namespace {

constexpr Stamp kFramePeriod = 100'000'000;               // 10 Hz
const SE3 kLeftRight(SO3(), Eigen::Vector3d(0.5, 0, 0));  // the right camera 0.5 m to the right

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

std::unique_ptr<VisualProvider> StereoProvider(const test::SimulatedCamera& camera) {
  auto provider = VisualProvider::Create({}, camera.model(), SE3());
  EXPECT_TRUE(provider) << provider.error();
  if (!provider) return nullptr;
  const auto model = std::make_shared<PinholeRadtan>(camera.model());
  const Status stereo = (*provider)->SetStereo({model, model, kLeftRight});
  EXPECT_TRUE(stereo.ok()) << stereo.message();
  return std::move(*provider);
}

TEST(StereoProvider, LandmarksStartWithThePairsDepth) {
  const auto camera = test::SimulatedCamera::Create("urban", 8.0, 3);
  ASSERT_NE(camera, nullptr);
  ASSERT_TRUE(camera->AddRightCamera(kLeftRight));
  const std::unique_ptr<VisualProvider> provider = StereoProvider(*camera);
  ASSERT_NE(provider, nullptr);
  FactorGraph graph;
  provider->Attach(graph);
  std::vector<PoseArray> poses;  // T_world_camera of each node (the body is the left camera)
  poses.reserve(4);
  const PoseBlockOf pose_of = [&](long id) { return poses[static_cast<std::size_t>(id)].data(); };
  std::vector<std::string> warnings;
  std::vector<TrackedFrame> tracked;
  const Stamp t0 = camera->begin() + 3'000'000'000;
  for (int k = 0; k < 4; ++k) {  // min_track_length (4) nodes
    const Stamp t = t0 + Stamp{k} * kFramePeriod;
    ASSERT_TRUE(provider->AddFrame(t, camera->Render(t), tracked, warnings));
    EXPECT_FALSE(provider->NextNodeStamp(t0)) << "the left frame waits for its right frame";
    provider->AddRightFrame(t, camera->RenderRight(t), warnings);
    EXPECT_EQ(provider->NextNodeStamp(t0), t);
    poses.push_back(PoseBlock(camera->CameraPose(t)));
    graph.AddPoseBlock(poses.back().data());
    provider->Observe(k, t);
    provider->Link(graph, pose_of);
  }
  EXPECT_TRUE(warnings.empty());
  SensorFactorStats stats;
  provider->Report(stats);
  EXPECT_EQ(stats.stereo_pairs, 4);
  const auto landmarks = provider->Landmarks();
  ASSERT_GT(landmarks.size(), 40u);
  // Most from their anchor's pair (measured 58 of 70), the others triangulated.
  EXPECT_GT(stats.stereo_depths, 0.7 * static_cast<double>(landmarks.size()));
  // Each depth's error in units of what a disparity error of 0.5 px gives at its depth z: sigma_z = z^2
  // sigma_d / (f b), with f = 400 px and b = 0.5 m (2.5 % of 20 m).
  std::vector<double> sigmas;
  for (const auto& landmark : landmarks) {
    const SE3 anchor = camera->CameraPose(t0);
    const auto point = camera->PointAlong(anchor, landmark.normalized.homogeneous());
    if (!point) continue;
    const double depth = (anchor.inverse() * *point).z();
    sigmas.push_back(std::abs(1.0 / *landmark.inverse_depth - depth) / (depth * depth * 0.5 / (400 * 0.5)));
  }
  ASSERT_GT(sigmas.size(), 30u);
  EXPECT_LT(Median(sigmas), 1.0);  // measured 0.54
  // Both cameras' factors at the true poses: the tracks' error, well within a pixel (1 sigma) for most.
  std::vector<double> errors;
  int anchor_factors = 0;
  for (const Factor& f : graph.Entries(FactorKind::kVisual)) {
    double r[2];
    ASSERT_TRUE(f.cost->Evaluate(f.blocks.data(), r, nullptr));
    errors.push_back(std::hypot(r[0], r[1]));
    anchor_factors += f.blocks.size() == 2;  // StereoAnchorFactor: inverse depth and t_d
  }
  EXPECT_GT(anchor_factors, 30);
  EXPECT_GT(stats.stereo_factors, anchor_factors);  // the later nodes' right observations too
  EXPECT_LT(Median(errors), 0.5);                   // measured 0.36
}

TEST(StereoProvider, RightFramesThatDoNotFitLeaveTheLeftFrameAlone) {
  const auto camera = test::SimulatedCamera::Create("urban", 4.0, 3);
  ASSERT_NE(camera, nullptr);
  const std::unique_ptr<VisualProvider> provider = StereoProvider(*camera);
  ASSERT_NE(provider, nullptr);
  std::vector<std::string> warnings;
  std::vector<TrackedFrame> tracked;
  const Stamp t0 = camera->begin() + 1'000'000'000, t1 = t0 + kFramePeriod, t2 = t1 + kFramePeriod;
  // A right frame before any left one, then a left frame whose right frame never comes: it goes on alone
  // when the next left frame comes.
  provider->AddRightFrame(t0 - kFramePeriod, camera->Render(t0), warnings);
  ASSERT_TRUE(provider->AddFrame(t0, camera->Render(t0), tracked, warnings));
  EXPECT_FALSE(provider->NextNodeStamp(t0));
  ASSERT_TRUE(provider->AddFrame(t1, camera->Render(t1), tracked, warnings));
  EXPECT_EQ(provider->NextNodeStamp(t0), t0);
  EXPECT_TRUE(warnings.empty());
  // A right frame of another size: the pair cannot be matched, the left frame goes on alone.
  Image small;
  small.width = 320, small.height = 240, small.channels = 1;
  small.pixels.assign(320 * 240, 128);
  provider->AddRightFrame(t1, small, warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("stereo pair at"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("the left frame is used alone"), std::string::npos) << warnings[0];
  EXPECT_EQ(provider->NextNodeStamp(t1), t1);
  // The next pair matches.
  ASSERT_TRUE(provider->AddFrame(t2, camera->Render(t2), tracked, warnings));
  provider->AddRightFrame(t2, camera->Render(t2), warnings);
  EXPECT_EQ(provider->NextNodeStamp(t2), t2);
  SensorFactorStats stats;
  provider->Report(stats);
  EXPECT_EQ(stats.stereo_pairs, 1);
}

TEST(StereoProvider, ARigWithoutABaselineIsRefused) {
  const auto camera = test::SimulatedCamera::Create("urban", 2.0, 3);
  ASSERT_NE(camera, nullptr);
  auto provider = VisualProvider::Create({}, camera->model(), SE3());
  ASSERT_TRUE(provider);
  const auto model = std::make_shared<PinholeRadtan>(camera->model());
  const Status same = (*provider)->SetStereo({model, model, SE3()});
  EXPECT_NE(same.message().find("no baseline"), std::string::npos) << same.message();
  const Status none = (*provider)->SetStereo({model, nullptr, kLeftRight});
  EXPECT_NE(none.message().find("no camera model"), std::string::npos) << none.message();
}

}  // namespace
}  // namespace uf::estimator
