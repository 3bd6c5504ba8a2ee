// ScenePath: resampling, nearest-point queries against a brute-force reference, polygon clearance.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "odometry/sim/scene/scene_path.h"

namespace uf::sim {
namespace {

Trajectory Circle(double radius, int n) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    const double a = 1.5 * std::numbers::pi * i / (n - 1);  // three quarters of a circle
    t.stamps.push_back(static_cast<Stamp>(i) * 10'000'000);
    t.poses.emplace_back(SO3(), Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), 0.1 * a));
  }
  return t;
}

TEST(ScenePath, ResamplesByArcLength) {
  const auto path = ScenePath::FromTrajectory(Circle(20.0, 400), 1.0, 1.5);
  ASSERT_TRUE(path.ok()) << path.error();
  // Chord length of 399 segments of a 0.75-circle, close to the arc 1.5 pi r.
  EXPECT_NEAR(path->length(), 1.5 * std::numbers::pi * 20.0, 0.01);
  for (std::size_t k = 1; k < path->samples().size(); ++k) {
    const auto& a = path->samples()[k - 1];
    const auto& b = path->samples()[k];
    EXPECT_NEAR((b.position - a.position).head<2>().norm(), path->spacing(), 1e-3);
    // Heading of a counter-clockwise circle at angle phi is phi + pi / 2.
    const double phi = std::atan2(b.position.y(), b.position.x());
    EXPECT_NEAR(std::remainder(b.heading - phi - std::numbers::pi / 2.0, 2.0 * std::numbers::pi), 0.0, 0.03);
  }
}

TEST(ScenePath, NearestPointMatchesBruteForce) {
  const auto path = ScenePath::FromTrajectory(Circle(30.0, 300), 1.0, 1.8);
  ASSERT_TRUE(path.ok());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-120.0, 120.0);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector2d p(u(rng), u(rng));
    double best = std::numeric_limits<double>::infinity();
    const auto& s = path->samples();
    for (std::size_t i = 0; i + 1 < s.size(); ++i) {
      const Eigen::Vector2d a = s[i].position.head<2>(), b = s[i + 1].position.head<2>();
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - p).norm());
    }
    const ScenePath::Nearest nearest = path->NearestPoint(p.x(), p.y());
    EXPECT_NEAR(nearest.distance, best, 1e-9);
    // Inside the circle is to the left of a counter-clockwise track.
    if (best > 1.0 && p.norm() < 29.0 && std::atan2(p.y(), p.x()) > 0.1) {
      EXPECT_GT(nearest.lateral, 0.0);
    }
  }
  EXPECT_NEAR(path->GroundHeight(30.0, 0.0), 0.0 - 1.8, 1e-9);
}

TEST(ScenePath, PolygonClearance) {
  Trajectory t;
  t.stamps = {0, 1};
  t.poses = {SE3(SO3(), {0, 0, 0}), SE3(SO3(), {100, 0, 0})};
  const auto path = ScenePath::FromTrajectory(t);
  ASSERT_TRUE(path.ok());
  auto square = [](double cx, double cy) {
    return std::vector<Eigen::Vector2d>{
        {cx - 1, cy - 1}, {cx + 1, cy - 1}, {cx + 1, cy + 1}, {cx - 1, cy + 1}};
  };
  EXPECT_TRUE(path->PolygonClear(square(50, 4.1), 3.0));    // 3.1 m away
  EXPECT_FALSE(path->PolygonClear(square(50, 3.9), 3.0));   // 2.9 m away
  EXPECT_FALSE(path->PolygonClear(square(50, 0.0), 3.0));   // straddles the track
  EXPECT_TRUE(path->PolygonClear(square(-4.5, 0.0), 3.0));  // before the start: 3.5 m
  // Extended by 10 m, the same square is on the track.
  EXPECT_FALSE(path->Extended(10.0).PolygonClear(square(-4.5, 0.0), 3.0));
  EXPECT_NEAR(path->Extended(10.0).length(), 120.0, 1e-9);
}

TEST(ScenePath, RejectsBadInput) {
  Trajectory one;
  one.stamps = {0};
  one.poses = {SE3()};
  const auto a = ScenePath::FromTrajectory(one);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("at least 2 poses"), std::string::npos);
  Trajectory two;
  two.poses = {SE3(), SE3(SO3(), {1, 0, 0})};
  EXPECT_FALSE(ScenePath::FromTrajectory(two, 0.0).ok());
  two.poses[1] = SE3(SO3(), {std::nan(""), 0, 0});
  EXPECT_FALSE(ScenePath::FromTrajectory(two).ok());
}

TEST(ScenePath, StandingStillGivesATrackAlongTheBodyX) {
  Trajectory still;
  still.stamps = {0, 1, 2};
  const SO3 yaw = SO3::Exp({0, 0, 0.8});
  still.poses = {SE3(yaw, {1, 2, 3}), SE3(yaw, {1, 2, 3}), SE3(yaw, {1, 2, 3})};
  const auto path = ScenePath::FromTrajectory(still);
  ASSERT_TRUE(path.ok());
  EXPECT_NEAR(path->samples().front().heading, 0.8, 1e-12);
  EXPECT_NEAR(path->Extended(5.0).length(), 10.0, 1e-2);
}

}  // namespace
}  // namespace uf::sim
