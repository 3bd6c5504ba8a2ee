// HandheldSceneTrajectory: measured from the poses and from the spline fitted to them (what every sensor
// and groundtruth.tum sample), independently of how they were made: standing still for the first second,
// the peak body rate, the looking around, the walking bounce (amplitude and frequency by a discrete Fourier
// transform) and sway, the steps between scans 0.5 s apart, the fit, the vehicle's path, and the clearance
// to the warehouse's racks. The vehicle motion is pinned to its poses before the handheld one existed.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/scene/handheld_trajectory.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/trajectory_spline.h"
#include "tests/support/triangle_distance.h"

namespace uf::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kDt = 0.01;                // s between poses
constexpr Stamp kKnotSpacing = 20'000'000;  // ns, the sequence's for handheld (kHandheldKnotSpacingS)
constexpr Stamp kStart = 1'700'000'000'000'000'000;

HandheldTrajectory Handheld(const std::string& scene, double duration_s, std::uint64_t seed) {
  auto handheld = HandheldSceneTrajectory(scene, duration_s, seed, kStart);
  EXPECT_TRUE(handheld.ok()) << handheld.error();
  return *handheld;
}

// The amplitude of the component of `x` (sampled every kDt) at `frequency`: |2/N sum x_n e^{-i w t_n}|.
double Amplitude(const std::vector<double>& x, double frequency) {
  double re = 0.0, im = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double phase = 2.0 * std::numbers::pi * frequency * static_cast<double>(n) * kDt;
    re += x[n] * std::cos(phase);
    im -= x[n] * std::sin(phase);
  }
  return 2.0 * std::hypot(re, im) / static_cast<double>(x.size());
}

// The frequency (0.25 to 5 Hz, 0.01 Hz steps) with the largest amplitude, and that amplitude.
std::pair<double, double> Dominant(const std::vector<double>& x) {
  std::pair<double, double> best{0.0, 0.0};
  for (double f = 0.25; f <= 5.0; f += 0.01) {
    const double a = Amplitude(x, f);
    if (a > best.second) best = {f, a};
  }
  return best;
}

class HandheldTest : public ::testing::TestWithParam<std::string> {};

TEST_P(HandheldTest, StandsStillThenWalksAndLooksAroundFast) {
  const HandheldTrajectory h = Handheld(GetParam(), 20.0, 4);
  const Trajectory& t = h.poses;
  ASSERT_EQ(t.size(), 2001u);
  ASSERT_EQ(h.path.stamps, t.stamps);
  for (std::size_t i = 0; i < t.size(); ++i) ASSERT_EQ(t.stamps[i], kStart + Stamp(i) * 10'000'000);

  // Exactly still for the first second, at the origin heading east.
  for (std::size_t i = 0; i <= 100; ++i) {
    ASSERT_EQ(t.poses[i].translation(), Eigen::Vector3d::Zero()) << i;
    ASSERT_EQ(t.poses[i].rotation(), Eigen::Matrix3d::Identity()) << i;
  }
  EXPECT_GT(t.poses[150].translation().norm(), 0.0);

  // Body rates by central differences of the poses: the peak is the target, >= 90 deg/s.
  double peak = 0.0;
  for (std::size_t i = 1; i + 1 < t.size(); ++i)
    peak = std::max(peak, (t.poses[i - 1].so3().inverse() * t.poses[i + 1].so3()).Log().norm() / (2 * kDt));
  EXPECT_GE(peak, 90.0 * kDeg);
  EXPECT_NEAR(peak, kHandheldPeakRateDegS * kDeg, 0.5 * kDeg);
  EXPECT_NEAR(h.peak_rate_rad_s, peak, 1e-9);

  // Looking around the path's heading: yaw +-30-70 deg, the body's z axis tilted by 8-30 deg at most.
  double yaw = 0.0, tilt = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Eigen::Matrix3d R = h.path.poses[i].rotation().transpose() * t.poses[i].rotation();
    yaw = std::max(yaw, std::abs(std::atan2(R(1, 0), R(0, 0))));
    tilt = std::max(tilt, std::acos(std::min(1.0, t.poses[i].rotation()(2, 2))));
  }
  EXPECT_GT(yaw, 30.0 * kDeg);
  EXPECT_LT(yaw, 70.0 * kDeg);
  EXPECT_GT(tilt, 8.0 * kDeg);
  EXPECT_LT(tilt, 30.0 * kDeg);

  // Scans 0.5 s apart (2 Hz keyframes): up to ~30 deg and ~0.65 m between consecutive ones.
  double step_rotation = 0.0, step_translation = 0.0;
  for (std::size_t i = 0; i + 50 < t.size(); i += 50) {
    step_rotation =
        std::max(step_rotation, (t.poses[i].so3().inverse() * t.poses[i + 50].so3()).Log().norm());
    step_translation =
        std::max(step_translation, (t.poses[i + 50].translation() - t.poses[i].translation()).norm());
  }
  EXPECT_GT(step_rotation, 20.0 * kDeg);
  EXPECT_LT(step_rotation, 45.0 * kDeg);
  EXPECT_GT(step_translation, 0.55);
  EXPECT_LT(step_translation, 0.75);
}

TEST_P(HandheldTest, BouncesAtTheStepFrequencyAndSwaysAtHalfOfIt) {
  const HandheldTrajectory h = Handheld(GetParam(), 16.0, 2);
  const Trajectory& t = h.poses;
  // The spline the sequence is made from, sampled every 10 ms from 4 s on (after the ramp).
  auto spline = TrajectorySpline::FitPoses(t, kKnotSpacing);
  ASSERT_TRUE(spline.ok()) << spline.error();
  std::vector<Eigen::Vector3d> p;
  for (std::size_t i = 400; i < t.size(); ++i) p.push_back(spline->Pose(t.stamps[i]).translation());

  // Vertical: the height minus its centred 1 s moving average (which removes the path's slow hills and
  // keeps a ~1.9 Hz oscillation to within 5 %).
  std::vector<double> bounce;
  for (std::size_t i = 50; i + 50 < p.size(); ++i) {
    double mean = 0.0;
    for (std::size_t j = i - 50; j < i + 50; ++j) mean += p[j].z();
    bounce.push_back(p[i].z() - mean / 100.0);
  }
  const auto [step_hz, bounce_m] = Dominant(bounce);
  EXPECT_GE(step_hz, 1.78);
  EXPECT_LE(step_hz, 2.02);
  EXPECT_GT(bounce_m, 0.022);  // ~+-3 cm
  EXPECT_LT(bounce_m, 0.034);
  const auto [low, high] = std::minmax_element(bounce.begin(), bounce.end());
  EXPECT_GT(*high - *low, 0.045);  // peak to peak
  EXPECT_LT(*high - *low, 0.08);

  // Sideways: the offset from the walker's path along its left, at half the step frequency.
  std::vector<double> sway;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const SE3& c = h.path.poses[400 + i];
    sway.push_back((p[i] - c.translation()).dot(c.rotation().col(1)));
  }
  const auto [sway_hz, sway_m] = Dominant(sway);
  EXPECT_NEAR(sway_hz, step_hz / 2.0, 0.03);
  EXPECT_GT(sway_m, 0.012);
  EXPECT_LT(sway_m, 0.028);
}

TEST_P(HandheldTest, TheSplineFollowsThePosesAndStandsStillToo) {
  const HandheldTrajectory h = Handheld(GetParam(), 12.0, 6);
  const Trajectory& t = h.poses;
  auto spline = TrajectorySpline::FitPoses(t, kKnotSpacing);
  ASSERT_TRUE(spline.ok()) << spline.error();
  double position_error = 0.0, rotation_error = 0.0, rate_error = 0.0, peak = 0.0;
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    const TrajectorySpline::State s = spline->Evaluate(t.stamps[i]);
    position_error =
        std::max(position_error, (s.T_world_body.translation() - t.poses[i].translation()).norm());
    rotation_error =
        std::max(rotation_error, (t.poses[i].so3().inverse() * s.T_world_body.so3()).Log().norm());
    const Eigen::Vector3d rate = (t.poses[i - 1].so3().inverse() * t.poses[i + 1].so3()).Log() / (2 * kDt);
    rate_error = std::max(rate_error, (s.angular_velocity_body - rate).norm());
    peak = std::max(peak, s.angular_velocity_body.norm());
  }
  EXPECT_LT(position_error, 1e-4);         // m
  EXPECT_LT(rotation_error, 1e-3 * kDeg);  // rad
  EXPECT_LT(rate_error, 0.5 * kDeg);       // rad/s, against the central differences
  EXPECT_GE(peak, 90.0 * kDeg);            // what the IMU measures
  // 0.1 s knots would smooth the ~4 Hz heel strike away: millimetres off, where 20 ms knots are exact.
  auto coarse = TrajectorySpline::FitPoses(t, 100'000'000);
  ASSERT_TRUE(coarse.ok());
  double coarse_error = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i)
    coarse_error =
        std::max(coarse_error, (coarse->Pose(t.stamps[i]).translation() - t.poses[i].translation()).norm());
  EXPECT_GT(coarse_error, 10 * position_error);
  // Standing still: no motion leaks out of the ramp into the first 0.9 s.
  for (Stamp time = spline->begin(); time <= spline->begin() + 900'000'000; time += 5'000'000) {
    const TrajectorySpline::State s = spline->Evaluate(time);
    ASSERT_LT(s.velocity_world.norm(), 1e-5) << time;
    ASSERT_LT(s.angular_velocity_body.norm(), 1e-5) << time;
    ASSERT_LT(s.acceleration_world.norm(), 1e-4) << time;
  }
}

TEST_P(HandheldTest, WalksTheVehiclesPath) {
  // The walker's path lies on the vehicle's (the same curvature over arc length), at walking speed, as far
  // as the vehicle drives in the same time (the corridor's is slower than a walker).
  const HandheldTrajectory h = Handheld(GetParam(), 20.0, 3);
  auto vehicle = DefaultSceneTrajectory(GetParam(), 20.0, 3, kStart);
  ASSERT_TRUE(vehicle.ok());
  double driven = 0.0, walked = 0.0, farthest = 0.0;
  for (std::size_t k = 1; k < vehicle->size(); ++k)
    driven += (vehicle->poses[k].translation() - vehicle->poses[k - 1].translation()).head<2>().norm();
  std::size_t j = 0;  // the vehicle's segment nearest the last walker's point
  for (std::size_t i = 0; i < h.path.size(); ++i) {
    if (i > 0) walked += (h.path.poses[i].translation() - h.path.poses[i - 1].translation()).head<2>().norm();
    if (walked > driven - 1.0) break;
    const Eigen::Vector2d q = h.path.poses[i].translation().head<2>();
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = j; k + 1 < vehicle->size(); ++k) {
      const Eigen::Vector2d a = vehicle->poses[k].translation().head<2>();
      const Eigen::Vector2d b = vehicle->poses[k + 1].translation().head<2>();
      const double length2 = (b - a).squaredNorm();
      const double s = length2 > 0 ? std::clamp((q - a).dot(b - a) / length2, 0.0, 1.0) : 0.0;
      const double d = (a + s * (b - a) - q).norm();
      if (d < best) best = d, j = k;
      if (d > best + 1.0) break;  // past the nearest segment along the path
    }
    farthest = std::max(farthest, best);
  }
  EXPECT_LT(farthest, 1e-3);
  EXPECT_LT(walked, kWalkingSpeed * 20.0);
  EXPECT_GT(walked, 0.5 * std::min(driven, kWalkingSpeed * 20.0));
}

INSTANTIATE_TEST_SUITE_P(Scenes, HandheldTest,
                         ::testing::Values("wild", "warehouse", "urban", "corridor", "tunnel"));

TEST(HandheldSceneTrajectory, SeededAndErrors) {
  const HandheldTrajectory a = Handheld("wild", 8.0, 1), b = Handheld("wild", 8.0, 1);
  const HandheldTrajectory c = Handheld("wild", 8.0, 2);
  EXPECT_EQ(a.poses.poses.back().matrix(), b.poses.poses.back().matrix());
  EXPECT_NE(a.poses.poses.back().matrix(), c.poses.poses.back().matrix());
  auto unknown = HandheldSceneTrajectory("moon", 10.0, 1, 0);
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().find("unknown scene 'moon'"), std::string::npos) << unknown.error();
  auto short_one = HandheldSceneTrajectory("wild", 1.0, 1, 0);
  ASSERT_FALSE(short_one.ok());
  EXPECT_NE(short_one.error().find("duration_s"), std::string::npos) << short_one.error();
}

TEST(HandheldSceneTrajectory, KeepsClearOfTheWarehouseRacks) {
  // The scene is laid out along the walker's path; the device sways off it by centimetres, so it stays
  // within a few cm of the clearance the racks keep from the path (the vehicle's device stays on it).
  const HandheldTrajectory h = Handheld("warehouse", 30.0, 5);
  SceneOptions options{"warehouse", 5, h.path, 1.4};
  auto scene = BuildScene(options);
  ASSERT_TRUE(scene.ok()) << scene.error();
  const TriangleMesh& mesh = scene->mesh;
  double nearest = std::numeric_limits<double>::infinity();
  int racks = 0;
  for (std::size_t k = 0; k < mesh.triangle_count(); ++k) {
    const Material material = mesh.materials[k];
    if (material != Material::kShelfSteel && material != Material::kCardboard)
      continue;  // not floor, walls, roof
    ++racks;
    const Eigen::Vector3i& tri = mesh.triangles[k];
    for (std::size_t i = 0; i < h.poses.size(); i += 10) {
      const Eigen::Vector3d device = h.poses.poses[i].translation();
      nearest =
          std::min(nearest, uf::testing::PointTriangleDistance(device, mesh.vertices[tri[0]].cast<double>(),
                                                               mesh.vertices[tri[1]].cast<double>(),
                                                               mesh.vertices[tri[2]].cast<double>()));
    }
  }
  ASSERT_GT(racks, 100);
  EXPECT_GT(nearest, SceneClearance("warehouse") - 0.03);
  EXPECT_LT(nearest, 3.0);  // the aisles are narrow: the racks are near
}

TEST(DefaultSceneTrajectory, VehicleMotionIsUnchanged) {
  // Poses of the vehicle motion (seed 3, 30 s) as the code before the handheld motion gave them (the
  // handheld motion shares its path integration): any change to the vehicle's output shows here.
  struct Pinned {
    const char* scene;
    std::size_t index;
    Eigen::Vector3d position;
    Eigen::Vector3d rotation;  // Log of R_world_body
  };
  const Pinned pinned[] = {
      {"urban",
       150,
       {0.0052822998331466817, 0, 2.5715190292166512e-05},
       {7.3767618659198428e-05, -0.0067381626785357343, 2.4853004791110435e-07}},
      {"urban",
       1234,
       {68.710990697367762, -1.8704410971111884, -1.64313501029492},
       {0.0020358354990211128, 0.056395733986832432, -0.15825180925072477}},
      {"urban",
       2999,
       {204.00962310858623, -23.973669626559911, -3.2105457862716364},
       {0.015881864625420791, 0.00250362729973014, -0.76317680912142749}},
      {"wild",
       150,
       {0.0064654686458450157, 0, 0.00064335288710970495},
       {0.00051092544749947873, -0.10236821587660584, 2.6174124920821782e-05}},
      {"wild",
       1234,
       {26.910710036176209, 3.8831752097355294, -0.35358512451980628},
       {-0.050817115350844322, 0.013501590382910097, 0.43718495424097759}},
      {"wild",
       2999,
       {78.965050742455148, 5.2481907091368534, -0.22352285776740105},
       {-0.046242852376685059, -0.1062356397708404, -0.26435032160196337}},
      {"warehouse",
       150,
       {0.0070408950611255761, 0, 0},
       {0.00012696820966127964, -0.0013167548537017864, 8.3593015359057611e-08}},
      {"warehouse",
       1234,
       {14.760000000000369, 0, 0},
       {0.0015150549685741619, -0.0035430793498923336, 2.6839833077174587e-06}},
      {"warehouse",
       2999,
       {19.780987523943132, -9.1817258178974832, 0},
       {0.0043034079393954837, 0.0031489510804671998, -3.141585381737193}},
      {"corridor",
       150,
       {0.0056327160489004578, 0, 0},
       {-8.9218720412866337e-05, -0.0011004732266448605, -4.9091411551811023e-08}},
      {"corridor",
       1234,
       {11.807822674351938, -0.030579278672234665, 0},
       {0.0062963768053314485, -0.0017670149941209172, -0.019498321872457196}},
      {"corridor",
       2999,
       {32.951966474513917, -1.2407060583328078, 0},
       {-0.0079634411795554746, -0.001379545190208592, -0.060627906884398848}},
      {"tunnel",
       150,
       {0.003410141886616857, 0, 3.7593299926808044e-05},
       {1.6642546973890484e-05, -0.012286380534042952, 1.0223961872710048e-07}},
      {"tunnel",
       1234,
       {91.555984251841849, -0.0070781501026906755, 0.2133121290168396},
       {-0.0056682082635818396, 0.012246736474437725, -0.0010604635183482471}},
      {"tunnel",
       2999,
       {299.205801714887, -13.259297503767639, -3.8249755825288876},
       {0.0096234720932741671, 0.02580634656456313, -0.10685637738084536}},
  };
  for (const Pinned& p : pinned) {
    auto t = DefaultSceneTrajectory(p.scene, 30.0, 3, kStart);
    ASSERT_TRUE(t.ok());
    const SE3& pose = t->poses[p.index];
    EXPECT_LT((pose.translation() - p.position).norm(), 1e-9) << p.scene << " " << p.index;
    EXPECT_LT((SO3::Exp(p.rotation).inverse() * pose.so3()).Log().norm(), 1e-12) << p.scene << " " << p.index;
  }
}

}  // namespace
}  // namespace uf::sim
