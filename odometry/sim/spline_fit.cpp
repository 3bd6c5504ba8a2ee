// TrajectorySpline::FitPoses: least-squares fit of the spline's control points to a recorded trajectory.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "odometry/sim/banded_least_squares.h"
#include "odometry/sim/cumulative_spline.h"
#include "odometry/sim/trajectory_spline.h"

namespace uf {
namespace {

constexpr double kSmoothnessWeight = 1e-6;  // of one second difference against one pose residual
constexpr long double kMaxSegments = 1e6;   // ~2 GB of rotation normal equations: 14 h at 50 ms knots
constexpr int kMaxIterations = 30;          // Gauss-Newton, rotations
constexpr double kConvergedStep = 1e-10;    // rad, largest control-rotation update that ends the iterations
constexpr double kAcceptableStep = 1e-6;    // rad, the largest last update still counted as converged

// Where the spline's segments lie: it starts at the first stamp and its last segment covers the last one.
struct Grid {
  Stamp begin = 0;
  Stamp spacing = 0;
  int segments = 0;
  int control_points() const { return segments + 3; }
  Stamp ControlTime(int i) const { return begin + (i - 1) * spacing; }
};

Status ValidatePoses(const Trajectory& poses, Stamp knot_spacing) {
  if (poses.size() < 4) {
    return Status::Error("a spline fit needs at least 4 poses, got " + std::to_string(poses.size()));
  }
  if (!poses.has_stamps()) {
    return Status::Error(
        "a spline fit needs stamped poses; the trajectory has none (KITTI poses without times?)");
  }
  if (poses.stamps.size() != poses.size()) {
    return Status::Error("trajectory has " + std::to_string(poses.stamps.size()) + " stamps for " +
                         std::to_string(poses.size()) + " poses");
  }
  if (knot_spacing <= 0) {
    return Status::Error("spline knot spacing must be > 0 ns, got " + std::to_string(knot_spacing) + " ns");
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (i > 0 && poses.stamps[i] <= poses.stamps[i - 1]) {
      return Status::Error("trajectory stamps must be strictly increasing: pose " + std::to_string(i) +
                           " at " + FormatSeconds(poses.stamps[i]) + " s follows " +
                           FormatSeconds(poses.stamps[i - 1]) + " s");
    }
    if (!poses.poses[i].matrix().allFinite()) {
      return Status::Error("trajectory pose " + std::to_string(i) + " at " + FormatSeconds(poses.stamps[i]) +
                           " s is not finite");
    }
  }
  return Status();
}

Expected<Grid> MakeGrid(const std::vector<Stamp>& stamps, Stamp spacing) {
  // long double holds any int64 exactly, so neither the span nor the end can overflow unnoticed.
  const long double span = static_cast<long double>(stamps.back()) - static_cast<long double>(stamps.front());
  const long double segments = std::max(1.0L, std::ceil(span / static_cast<long double>(spacing)));
  if (segments > kMaxSegments) {
    return Status::Error("spline knot spacing " + std::to_string(spacing) +
                         " ns gives more than 1e6 segments over the stamps [" +
                         FormatSeconds(stamps.front()) + ", " + FormatSeconds(stamps.back()) + "] s");
  }
  if (static_cast<long double>(stamps.front()) + segments * static_cast<long double>(spacing) >
      static_cast<long double>(std::numeric_limits<Stamp>::max())) {
    return Status::Error("spline knot spacing " + std::to_string(spacing) +
                         " ns runs past the largest stamp");
  }
  return Grid{stamps.front(), spacing, static_cast<int>(segments)};
}

Expected<std::vector<Eigen::Vector3d>> FitPositions(const Grid& grid, const Trajectory& poses) {
  // Linear least squares: sum_k |sum_i B_i(u_k) c_{s_k + i} - p_k|^2 + w sum_j |c_{j-1} - 2 c_j + c_{j+1}|^2.
  spline::BandedLeastSquares problem(grid.control_points(), 1, 3);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const spline::SegmentCoordinate where =
        spline::LocateSegment(poses.stamps[k], grid.begin, grid.spacing, grid.segments);
    problem.Add(where.index, spline::PositionWeights(where.u).transpose(),
                poses.poses[k].translation().transpose());
  }
  const Eigen::RowVector3d second_difference(1.0, -2.0, 1.0);
  for (int j = 1; j + 1 < grid.control_points(); ++j) {
    problem.Add(j - 1, second_difference, Eigen::RowVector3d::Zero(), kSmoothnessWeight);
  }
  Expected<Eigen::MatrixXd> solution = problem.Solve();
  if (!solution.ok()) return Status::Error("spline position fit: " + solution.error());
  std::vector<Eigen::Vector3d> positions;
  for (Eigen::Index i = 0; i < solution->rows(); ++i) positions.push_back(solution->row(i).transpose());
  return positions;
}

// The poses' rotation slerped at each control point's time (clamped to the stamps): close to the fit, whose
// control rotations sit near the curve, so Gauss-Newton starts inside its basin.
std::vector<SO3> InitialRotations(const Grid& grid, const std::vector<Stamp>& stamps,
                                  const std::vector<SO3>& rotations) {
  std::vector<SO3> control;
  for (int i = 0; i < grid.control_points(); ++i) {
    const Stamp t = std::clamp(grid.ControlTime(i), stamps.front(), stamps.back());
    const auto after = std::upper_bound(stamps.begin(), stamps.end(), t);
    const std::size_t k =
        std::min<std::size_t>(std::max<std::ptrdiff_t>(after - stamps.begin() - 1, 0), stamps.size() - 2);
    const double s = static_cast<double>(t - stamps[k]) / static_cast<double>(stamps[k + 1] - stamps[k]);
    control.push_back(Slerp(rotations[k], rotations[k + 1], std::clamp(s, 0.0, 1.0)));
  }
  return control;
}

// One Gauss-Newton system for the right perturbations delta_i of the control rotations.
spline::BandedLeastSquares RotationNormalEquations(const Grid& grid, const std::vector<Stamp>& stamps,
                                                   const std::vector<SO3>& rotations,
                                                   const std::vector<SO3>& control) {
  spline::BandedLeastSquares problem(grid.control_points(), 3, 1);
  // Pose residual r_k = Log(R_k^T R(t_k)); R(t_k) -> R(t_k) Exp(eta) moves it by Jr^-1(r_k) eta, and
  // eta = sum_i J_i delta_i (RotationSegmentJacobians).
  for (std::size_t k = 0; k < stamps.size(); ++k) {
    const spline::SegmentCoordinate where =
        spline::LocateSegment(stamps[k], grid.begin, grid.spacing, grid.segments);
    std::array<SO3, 4> segment;
    for (int i = 0; i < 4; ++i) segment[i] = control[where.index + i];
    const SO3 fitted = spline::EvaluateRotationSegment(segment, where.u, 1.0).rotation;
    const Eigen::Vector3d residual = (rotations[k].inverse() * fitted).Log();
    const Eigen::Matrix3d Jr_inv = RightJacobianInverseSO3(residual);
    const std::array<Eigen::Matrix3d, 4> jacobians = spline::RotationSegmentJacobians(segment, where.u);
    Eigen::Matrix<double, 3, 12> J;
    for (int i = 0; i < 4; ++i) J.middleCols<3>(3 * i) = Jr_inv * jacobians[i];
    problem.Add(where.index, J, -residual);
  }
  // Smoothness residual q_j = d_{j+1} - d_j with d_j = Log(R_{j-1}^T R_j): zero at constant body rate.
  // d_j moves by Jr^-1(d_j) delta_j - Jl^-1(d_j) delta_{j-1}.
  for (int j = 1; j + 1 < grid.control_points(); ++j) {
    const Eigen::Vector3d d = (control[j - 1].inverse() * control[j]).Log();
    const Eigen::Vector3d d_next = (control[j].inverse() * control[j + 1]).Log();
    Eigen::Matrix<double, 3, 9> J;
    J << LeftJacobianInverseSO3(d), -LeftJacobianInverseSO3(d_next) - RightJacobianInverseSO3(d),
        RightJacobianInverseSO3(d_next);
    problem.Add(j - 1, J, -(d_next - d), kSmoothnessWeight);
  }
  return problem;
}

Expected<std::vector<SO3>> FitRotations(const Grid& grid, const Trajectory& poses) {
  std::vector<SO3> rotations;
  for (const SE3& pose : poses.poses) rotations.push_back(pose.so3().Normalized());
  std::vector<SO3> control = InitialRotations(grid, poses.stamps, rotations);
  double largest_step = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < kMaxIterations && largest_step > kConvergedStep; ++iteration) {
    Expected<Eigen::MatrixXd> step = RotationNormalEquations(grid, poses.stamps, rotations, control).Solve();
    if (!step.ok()) return Status::Error("spline rotation fit: " + step.error());
    largest_step = 0.0;
    for (int i = 0; i < grid.control_points(); ++i) {
      const Eigen::Vector3d delta = step->block<3, 1>(3 * i, 0);
      control[i] = control[i] * SO3::Exp(delta);
      largest_step = std::max(largest_step, delta.norm());
    }
  }
  if (largest_step > kAcceptableStep) {
    return Status::Error("spline rotation fit did not converge (last update " + std::to_string(largest_step) +
                         " rad): do the poses turn by close to pi between stamps or knots?");
  }
  return control;
}

}  // namespace

Expected<TrajectorySpline> TrajectorySpline::FitPoses(const Trajectory& poses, Stamp knot_spacing) {
  if (Status status = ValidatePoses(poses, knot_spacing); !status.ok()) return status;
  Expected<Grid> grid = MakeGrid(poses.stamps, knot_spacing);
  if (!grid.ok()) return grid.status();
  Expected<std::vector<Eigen::Vector3d>> positions = FitPositions(*grid, poses);
  if (!positions.ok()) return positions.status();
  Expected<std::vector<SO3>> rotations = FitRotations(*grid, poses);
  if (!rotations.ok()) return rotations.status();
  std::vector<SE3> control_points;
  for (int i = 0; i < grid->control_points(); ++i)
    control_points.emplace_back((*rotations)[i], (*positions)[i]);
  return TrajectorySpline(grid->begin, grid->spacing, std::move(control_points));
}

}  // namespace uf
