// The condensed factor (window/condensed_factor.h) against the residuals it replaces: at its linearization
// point its cost, gradient and Gauss-Newton Hessian are theirs (Huber-weighted point-to-plane factors on two
// poses, the LiDAR scan's case); a window solved on condensed scans reaches the optimum the exact solve
// reaches (a box room seen from four poses, started centimetres and a degree away); on a linear problem one
// round is exact.
#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/factors/pose_prior_factor.h"
#include "odometry/estimator/factors/projected_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/window/condensed_factor.h"
#include "odometry/estimator/window/dense_least_squares.h"
#include "odometry/estimator/window/factor_graph.h"

namespace uf::estimator {
namespace {

// Six walls of a 20 x 12 x 6 m room and points on them, in the world.
struct Room {
  std::vector<Plane> walls;
  Room() {
    const auto wall = [&](Eigen::Vector3d normal, Eigen::Vector3d point) {
      walls.push_back({normal, point, 0.05});
    };
    wall(Eigen::Vector3d::UnitX(), {-10, 0, 0});
    wall(-Eigen::Vector3d::UnitX(), {10, 0, 0});
    wall(Eigen::Vector3d::UnitY(), {0, -6, 0});
    wall(-Eigen::Vector3d::UnitY(), {0, 6, 0});
    wall(Eigen::Vector3d::UnitZ(), {0, 0, -1.5});
    wall(-Eigen::Vector3d::UnitZ(), {0, 0, 4.5});
  }
  // A point on wall w, uniformly within the room's extent.
  Eigen::Vector3d PointOn(int w, std::mt19937_64& random) const {
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::Vector3d p(9.5 * u(random), 5.5 * u(random), 1.5 + 2.5 * u(random));
    const Plane& plane = walls[w];
    return p - plane.normal * plane.normal.dot(p - plane.point);
  }
};

SE3 TruePose(int k) {  // driving along x, turning slowly
  return SE3(SO3::Exp(Eigen::Vector3d(0.01 * k, -0.005 * k, 0.05 * k)),
             Eigen::Vector3d(1.0 * k, 0.2 * k, 0.02 * k));
}

// A scan between poses b and e: points on the walls seen at fractions a of the sweep, in the LiDAR frame (the
// identity mount), with 2 cm of noise along the normal and one in twenty 0.5 m off (Huber outliers).
struct ScanPoint {
  Eigen::Vector3d lidar;
  double a;
  Plane plane;
  std::unique_ptr<PointToPlaneFactor> Factor() const {
    return std::make_unique<PointToPlaneFactor>(lidar, a, plane, SE3());
  }
};

std::vector<ScanPoint> Scan(const Room& room, int b, std::mt19937_64& random) {
  std::vector<ScanPoint> scan;
  std::uniform_real_distribution<double> fraction(0, 1);
  std::normal_distribution<double> noise(0, 0.02);
  for (int i = 0; i < 300; ++i) {
    const int w = i % 6;
    const double a = fraction(random);
    const Eigen::Vector3d world =
        room.PointOn(w, random) + room.walls[w].normal * (noise(random) + (i % 20 == 0 ? 0.5 : 0.0));
    const SE3 T_b = TruePose(b), T_e = TruePose(b + 1);
    const SO3 R = T_b.so3() * SO3::Exp(a * (T_b.so3().inverse() * T_e.so3()).Log());
    const Eigen::Vector3d t = (1 - a) * T_b.translation() + a * T_e.translation();
    scan.push_back({R.inverse() * (world - t), a, room.walls[w]});
  }
  return scan;
}

std::array<double, kPoseSize> Perturbed(const SE3& T, std::mt19937_64& random) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d dt(0.03 * n(random), 0.03 * n(random), 0.03 * n(random));
  const Eigen::Vector3d dr(0.015 * n(random), 0.015 * n(random), 0.015 * n(random));
  return PoseBlock(SE3(T.so3() * SO3::Exp(dr), T.translation() + dt));
}

TEST(CondensedFactor, HasTheResidualsCostGradientAndHessianAtItsPoint) {
  std::mt19937_64 random(3);
  const Room room;
  std::vector<std::unique_ptr<PointToPlaneFactor>> factors;
  for (const ScanPoint& point : Scan(room, 0, random)) factors.push_back(point.Factor());
  std::array<double, kPoseSize> begin = Perturbed(TruePose(0), random), end = Perturbed(TruePose(1), random);
  ceres::HuberLoss huber(1.0);
  const std::vector<double*> blocks = {begin.data(), end.data()};
  std::vector<CondensedInput> inputs;
  DenseLeastSquares exact;
  exact.AddPoseBlock(begin.data());
  exact.AddPoseBlock(end.data());
  for (const auto& f : factors) {
    inputs.push_back({f.get(), f.get(), &huber, &blocks});
    exact.AddResidualBlock(f.get(), &huber, blocks);
  }
  const std::vector<BlockLayout> layout = {{begin.data(), kPoseSize, kPoseTangentSize, BlockKind::kPose},
                                           {end.data(), kPoseSize, kPoseTangentSize, BlockKind::kPose}};
  Expected<std::unique_ptr<MarginalizationFactor>> condensed = CondenseResidualBlocks(inputs, layout, {});
  ASSERT_TRUE(condensed) << condensed.status().message();
  DenseLeastSquares model;
  model.AddPoseBlock(begin.data());
  model.AddPoseBlock(end.data());
  model.AddResidualBlock(condensed->get(), nullptr, {begin.data(), end.data()});
  double cost_exact = 0, cost_model = 0;
  Eigen::MatrixXd H_exact, H_model;
  Eigen::VectorXd g_exact, g_model;
  ASSERT_TRUE(exact.Linearize(&cost_exact, &H_exact, &g_exact));
  ASSERT_TRUE(model.Linearize(&cost_model, &H_model, &g_model));
  ASSERT_GT(cost_exact, 1.0);  // far from the optimum: a real gradient to match
  EXPECT_NEAR(cost_model, cost_exact, 1e-9 * cost_exact);
  EXPECT_LT((g_model - g_exact).cwiseAbs().maxCoeff(), 1e-9 * g_exact.cwiseAbs().maxCoeff());
  EXPECT_LT((H_model - H_exact).cwiseAbs().maxCoeff(), 1e-9 * H_exact.cwiseAbs().maxCoeff());
}

// Four poses, three scans; the first pose held (the gauge).
constexpr int kPoses = 4;
using Poses = std::array<std::array<double, kPoseSize>, kPoses>;

struct Window {
  std::vector<ScanPoint> scans[kPoses - 1];
  Poses start;
  explicit Window(std::uint64_t seed) {
    std::mt19937_64 random(seed);
    const Room room;
    for (int k = 0; k + 1 < kPoses; ++k) scans[k] = Scan(room, k, random);
    start[0] = PoseBlock(TruePose(0));
    for (int k = 1; k < kPoses; ++k) start[k] = Perturbed(TruePose(k), random);
  }
  void AddScan(FactorGraph& graph, Poses& poses, int k, const Eigen::Vector3d& wall_shift = {0, 0, 0}) const {
    for (const ScanPoint& point : scans[k]) {
      ScanPoint moved = point;
      moved.plane.point += wall_shift;
      graph.Add(FactorKind::kLidar, k, moved.Factor(), std::make_unique<ceres::HuberLoss>(1.0),
                {poses[k].data(), poses[k + 1].data()}, true);
    }
  }
  void AddTo(FactorGraph& graph, Poses& poses) const {
    for (auto& pose : poses) graph.AddPoseBlock(pose.data());
    for (int k = 0; k + 1 < kPoses; ++k) AddScan(graph, poses, k);
  }
  // condense: with the default relinearization thresholds, or (exact) with none: every model condensed anew
  // at each solve's result until the poses stop moving.
  static WindowSolveRequest Request(Poses& poses, bool condense, bool exact = false) {
    WindowSolveRequest request;
    for (int k = 1; k < kPoses; ++k) request.free.push_back(poses[k].data());
    request.max_iterations = condense ? 8 : 50;
    request.max_time_s = 100;
    if (condense) {
      request.condense = [](const Factor& f) { return f.kind == FactorKind::kLidar; };
      request.condensed_rounds = 5;
      if (exact)
        request.relinearize_translation_m = request.relinearize_rotation_rad = request.relinearize_euclidean =
            0;
    }
    return request;
  }
};

// Pose k of `a` and `b` agree to `m` and `rad`.
void ExpectSamePoses(const Poses& a, const Poses& b, double m, double rad) {
  for (int k = 1; k < kPoses; ++k) {
    const SE3 A = PoseFromBlock(a[k].data()), B = PoseFromBlock(b[k].data());
    EXPECT_LT((A.translation() - B.translation()).norm(), m) << k;
    EXPECT_LT((A.so3().inverse() * B.so3()).Log().norm(), rad) << k;
  }
}

// What a model kept within the default thresholds (5 mm, 0.5 mrad from its linearization point) may leave
// between its optimum and the exact one: the robust weights' and the rotation's change over that distance,
// second order in it. A twenty-fifth of the thresholds: 0.2 mm and 20 urad (the poses' own error against
// the room here is ~1 mm); a model of other entries would be centimetres off.
constexpr double kKeptModelM = 2e-4, kKeptModelRad = 2e-5;

// The exact solve (many LM iterations) and the condensed one end at the same poses, far closer to each other
// than to where they started: to 10 um and 1 urad when every model is condensed anew at each result, to the
// bound above with the default thresholds.
TEST(CondensedFactor, AWindowSolvedOnCondensedScansReachesTheExactOptimum) {
  const Window window(11);
  Poses exact = window.start, relinearized = window.start, condensed = window.start;
  FactorGraph exact_graph, relinearized_graph, condensed_graph;
  window.AddTo(exact_graph, exact);
  window.AddTo(relinearized_graph, relinearized);
  window.AddTo(condensed_graph, condensed);
  ASSERT_TRUE(exact_graph.Solve(Window::Request(exact, false)).usable);
  ASSERT_TRUE(relinearized_graph.Solve(Window::Request(relinearized, true, true)).usable);
  ExpectSamePoses(relinearized, exact, 1e-5, 1e-6);
  const WindowSolveResult result = condensed_graph.Solve(Window::Request(condensed, true));
  ASSERT_TRUE(result.usable);
  ExpectSamePoses(condensed, exact, kKeptModelM, kKeptModelRad);
  for (int k = 1; k < kPoses; ++k) {
    const SE3 E = PoseFromBlock(exact[k].data()), S = PoseFromBlock(window.start[k].data());
    ASSERT_GT((S.translation() - E.translation()).norm(), 0.01) << k;
    EXPECT_LT((E.translation() - TruePose(k).translation()).norm(), 0.01) << k;  // the optimum is the room's
  }
  // Solved again where it ended: every model holds, one solve on them, nothing moves.
  const Poses before = condensed;
  const WindowSolveResult again = condensed_graph.Solve(Window::Request(condensed, true));
  ASSERT_TRUE(again.usable);
  EXPECT_LT(again.iterations, result.iterations);
  ExpectSamePoses(condensed, before, 1e-9, 1e-9);
}

// A kept model never outlives its entries: a scan's factors replaced by others on the same poses (its walls
// moved 4 cm) are condensed anew, and the solve reaches the new problem's exact optimum.
TEST(CondensedFactor, ReplacedEntriesAreCondensedAnew) {
  const Window window(5);
  Poses exact = window.start, condensed = window.start;
  FactorGraph exact_graph, condensed_graph;
  window.AddTo(exact_graph, exact);
  window.AddTo(condensed_graph, condensed);
  ASSERT_TRUE(condensed_graph.Solve(Window::Request(condensed, true)).usable);
  const Eigen::Vector3d shift(0.04, -0.03, 0.02);
  condensed_graph.Remove(FactorKind::kLidar, 2);
  window.AddScan(condensed_graph, condensed, 2, shift);
  exact_graph.Remove(FactorKind::kLidar, 2);
  window.AddScan(exact_graph, exact, 2, shift);
  ASSERT_TRUE(exact_graph.Solve(Window::Request(exact, false)).usable);
  ASSERT_TRUE(condensed_graph.Solve(Window::Request(condensed, true)).usable);
  ExpectSamePoses(condensed, exact, kKeptModelM, kKeptModelRad);
}

// A cost changed in place (FactorGraph::ReplaceCosts, as the window's reliability scheduling wraps a scan's
// factors in a ProjectedFactor) is what the next solves use: the entries take the new cost's tangent
// Jacobians and new serials, so no model of the old cost serves them. Here the last scan's factors lose their
// say along the world's x translation and a prior pulls the last pose 10 cm along x (5 cm sigma): before,
// the room's walls hold it within 1 cm of the truth; after, only the prior says where it lies along x. (A
// solve on the residuals themselves would not follow: the projector drops Jacobian columns, not the
// residuals' dependence, so its steps along x raise the cost it tests them on; the window projects only
// directions the residuals hardly see.)
TEST(CondensedFactor, CostsReplacedInPlaceAreWhatTheNextSolvesUse) {
  const Window window(7);
  Poses poses = window.start;
  FactorGraph graph;
  window.AddTo(graph, poses);
  const SE3 pulled(TruePose(kPoses - 1).so3(),
                   TruePose(kPoses - 1).translation() + Eigen::Vector3d(0.1, 0, 0));
  graph.Add(FactorKind::kStatePrior, 0, MakePosePriorFactor(pulled, 0.05, 1.0), nullptr,
            {poses[kPoses - 1].data()});
  ASSERT_TRUE(graph.Solve(Window::Request(poses, true)).usable);
  const auto x_error = [&] { return poses[kPoses - 1][0] - TruePose(kPoses - 1).translation().x(); };
  EXPECT_LT(std::abs(x_error()), 0.01);

  const std::uint64_t serial_before = graph.Entries(FactorKind::kLidar).back().serial;
  Matrix6d drop_x = Matrix6d::Identity();
  drop_x(0, 0) = 0;
  graph.ReplaceCosts(FactorKind::kLidar, kPoses - 2, [&](std::unique_ptr<ceres::CostFunction> cost) {
    return std::unique_ptr<ceres::CostFunction>(std::make_unique<ProjectedFactor>(std::move(cost), drop_x));
  });
  const Factor& replaced = graph.Entries(FactorKind::kLidar).back();
  EXPECT_NE(dynamic_cast<const ProjectedFactor*>(replaced.cost.get()), nullptr);
  EXPECT_EQ(replaced.tangent, dynamic_cast<const TangentJacobianCost*>(replaced.cost.get()));
  EXPECT_GT(replaced.serial, serial_before);
  ASSERT_TRUE(graph.Solve(Window::Request(poses, true)).usable);
  EXPECT_NEAR(x_error(), 0.1, 0.005);
}

}  // namespace
}  // namespace uf::estimator
