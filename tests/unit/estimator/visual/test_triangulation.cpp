// Triangulation and the inverse-depth parameter against simulated landmarks: exact and noisy rays from known
// cameras, degenerate geometry, and tracks of the front end on simulated frames against the scene points
// their pixels see (the ray caster's truth).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "odometry/estimator/factors/reprojection_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/estimator/visual/triangulation.h"
#include "tests/unit/estimator/visual/simulated_camera.h"

namespace uf::estimator {
namespace {

Eigen::Vector2d Normalized(const SE3& T_world_cam, const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d p = T_world_cam.inverse() * p_world;
  return p.head<2>() / p.z();
}

// Cameras along a 2 m baseline looking along +z (the rig of a forward-moving car, seen from the side).
std::vector<SE3> Cameras(int n) {
  std::vector<SE3> cams;
  for (int k = 0; k < n; ++k)
    cams.emplace_back(SO3::Exp(Eigen::Vector3d(0, 0.02 * k, 0)), Eigen::Vector3d(2.0 * k / (n - 1), 0, 0));
  return cams;
}

TEST(Triangulation, RecoversLandmarksAndTheirInverseDepth) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> lateral(-5, 5), depth(5, 30);
  std::normal_distribution<double> pixel_noise(0, 0.5 / 400);  // 0.5 px at a 400 px focal length
  const std::vector<SE3> cams = Cameras(5);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d landmark(lateral(rng), lateral(rng) * 0.4, depth(rng));
    std::vector<Eigen::Vector2d> exact, noisy;
    for (const SE3& c : cams) {
      exact.push_back(Normalized(c, landmark));
      noisy.push_back(exact.back() + Eigen::Vector2d(pixel_noise(rng), pixel_noise(rng)));
    }
    auto t = Triangulate(cams, exact);
    ASSERT_TRUE(t) << t.error();
    EXPECT_LT((t->point_world - landmark).norm(), 1e-8);
    EXPECT_NEAR(InverseDepth(cams[0], t->point_world), 1 / (cams[0].inverse() * landmark).z(), 1e-10);
    EXPECT_LT(t->max_reprojection, 1e-10);
    // With noise sigma_u (normalized) the depth is fixed by the slope of u against the cameras' positions x_k
    // along the baseline (u_k = (X - x_k) / z): sigma_z = z^2 sigma_u / sqrt(sum (x_k - mean x)^2), with
    // sum = 2.5 m^2 for these five cameras (0.71 m at 30 m); the lateral error is far smaller. 4 sigma.
    auto n = Triangulate(cams, noisy);
    ASSERT_TRUE(n) << n.error();
    const double z = (cams[0].inverse() * landmark).z();
    const double sigma_z = z * z * (0.5 / 400) / std::sqrt(2.5);
    EXPECT_LT((n->point_world - landmark).norm(), 4 * sigma_z) << "depth " << z;
  }
}

TEST(Triangulation, RefusesDegenerateGeometry) {
  const std::vector<SE3> cams = Cameras(3);
  const Eigen::Vector3d far(0, 0, 2000);  // 2 m baseline: 0.06 deg of parallax
  std::vector<Eigen::Vector2d> u;
  for (const SE3& c : cams) u.push_back(Normalized(c, far));
  auto t = Triangulate(cams, u);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().find("parallax"), std::string::npos) << t.error();
  // Rays that meet behind the cameras.
  const Eigen::Vector3d behind(1, 0, -10);
  u.clear();
  for (const SE3& c : cams) u.push_back(Normalized(c, behind));
  t = Triangulate(cams, u);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().find("depth"), std::string::npos) << t.error();
  EXPECT_FALSE(Triangulate(std::span(cams).first(1), std::span(u).first(1)));
}

// Tracks of the front end over simulated frames, triangulated from the true camera poses: the points land on
// the scene surface the anchor pixel sees; the visual factor's residual there is small.
TEST(Triangulation, TracksOnSimulatedFramesLandOnTheScene) {
  const auto camera = test::SimulatedCamera::Create("urban", 8.0, 3);
  ASSERT_NE(camera, nullptr);
  auto tracker = FeatureTracker::Create(camera->model(), {});
  ASSERT_TRUE(tracker);
  struct Track {
    std::vector<SE3> poses;
    std::vector<Eigen::Vector2d> normalized;
    std::optional<Eigen::Vector3d> truth;
  };
  std::map<long, Track> tracks;
  for (int k = 0; k < 12; ++k) {
    const Stamp t = camera->begin() + 2'000'000'000 + Stamp{k} * 100'000'000;
    auto frame = tracker->Track(t, camera->Render(t));
    ASSERT_TRUE(frame);
    for (const TrackedFeature& f : frame->features) {
      Track& track = tracks[f.id];
      if (f.length == 1) track.truth = camera->PointAt(t, f.pixel);
      track.poses.push_back(camera->CameraPose(t));
      track.normalized.push_back(f.normalized);
    }
  }
  std::vector<double> depth_errors, residuals;  // depth errors in units of the allowed sigma
  for (const auto& [id, track] : tracks) {
    if (track.poses.size() < 4 || !track.truth) continue;
    auto t = Triangulate(track.poses, track.normalized);
    if (!t) continue;  // mostly too little parallax: points far ahead of a car driving forward
    const double depth = (track.poses.front().inverse() * *track.truth).z();
    // The depth error a track's geometry allows: sigma_z / z = sigma_u / sin(parallax), with the tracks'
    // precision sigma_u = 0.5 px (the figure) at the 400 px focal length.
    const double sigma_relative = (0.5 / 400) / std::sin(t->parallax_deg * std::numbers::pi / 180);
    depth_errors.push_back((t->point_world - *track.truth).norm() / depth / sigma_relative);
    // The factor between the first and last observation at the triangulated inverse depth, the true poses
    // and an identity extrinsic (the poses are the cameras'): 1.5 px sigma at 400 px.
    const ReprojectionFactor f({track.normalized.front(), {0, 0}}, {track.normalized.back(), {0, 0}}, 0, 0,
                               400 / 1.5);
    const auto pose_i = PoseBlock(track.poses.front()), pose_j = PoseBlock(track.poses.back());
    const auto extrinsic = PoseBlock(SE3());
    const double lambda = InverseDepth(track.poses.front(), t->point_world), td = 0;
    const double* blocks[] = {pose_i.data(), pose_j.data(), extrinsic.data(), &lambda, &td};
    Eigen::Vector2d r;
    f.Evaluate(blocks, r.data(), nullptr);
    residuals.push_back(r.norm());
  }
  ASSERT_GT(depth_errors.size(), 60u);  // of ~150 tracks 4 frames or longer
  std::sort(depth_errors.begin(), depth_errors.end());
  std::sort(residuals.begin(), residuals.end());

  EXPECT_LT(depth_errors[depth_errors.size() / 2], 2.0);         // median within 2 sigma (measured: 0.94)
  EXPECT_LT(residuals[residuals.size() / 2], 0.5);               // median below a third of a pixel
}

}  // namespace
}  // namespace uf::estimator
