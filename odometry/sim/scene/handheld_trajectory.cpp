#include "odometry/sim/scene/handheld_trajectory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "odometry/sim/scene/scene_placement.h"

namespace uf::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180.0;
constexpr double kStandStill = 1.0;  // s, as the path's
constexpr double kRamp = 2.0;        // s, of the walking speed and of r(t)
constexpr double kDt = 0.01;         // s, between poses
constexpr double kMinScale = 0.25, kMaxScale = 2.0;
constexpr int kScaleIterations = 30;

// S7(u) = 35u^4 - 84u^5 + 70u^6 - 20u^7, clamped to [0, 1] outside [0, 1].
double Smoothstep7(double u) {
  if (u <= 0.0) return 0.0;
  if (u >= 1.0) return 1.0;
  const double u2 = u * u;
  return u2 * u2 * (35.0 + u * (-84.0 + u * (70.0 - 20.0 * u)));
}

struct Sinusoid {
  double amplitude = 0.0, frequency = 0.0, phase = 0.0;  // amplitude sin(2 pi frequency t + phase)
};
using Sinusoids = std::array<Sinusoid, 3>;

double Evaluate(const Sinusoids& waves, double t) {
  double sum = 0.0;
  for (const Sinusoid& w : waves) sum += w.amplitude * std::sin(2.0 * kPi * w.frequency * t + w.phase);
  return sum;
}

// Three sinusoids of the given amplitudes (rad) at frequencies drawn in the three bands.
Sinusoids LookWaves(std::mt19937_64& rng, double slow, double middle, double fast) {
  constexpr std::array<std::pair<double, double>, 3> kBands = {{{0.1, 0.2}, {0.4, 0.8}, {0.9, 1.5}}};
  const std::array<double, 3> amplitudes = {slow, middle, fast};
  Sinusoids waves;
  for (std::size_t i = 0; i < waves.size(); ++i) {
    const double frequency = Uniform(rng, kBands[i].first, kBands[i].second);
    waves[i] = {amplitudes[i], frequency, Uniform(rng, 0.0, 2.0 * kPi)};
  }
  return waves;
}

struct Gait {
  double step_hz = 1.9, phase = 0.0;
  double bounce = 0.03, heel = 0.004, heel_phase = 0.0;  // m, m, rad
  double sway = 0.02, sway_phase = 0.0;                  // m, rad
  Sinusoids yaw, pitch, roll;                            // rad, before scaling
};

Gait DrawGait(std::mt19937_64& rng) {
  Gait g;
  g.step_hz = Uniform(rng, 1.8, 2.0);
  g.phase = Uniform(rng, 0.0, 2.0 * kPi);
  g.bounce = Uniform(rng, 0.026, 0.030);
  g.heel = Uniform(rng, 0.003, 0.005);
  g.heel_phase = Uniform(rng, 0.0, 2.0 * kPi);
  g.sway = Uniform(rng, 0.015, 0.025);
  g.sway_phase = Uniform(rng, 0.0, 2.0 * kPi);
  g.yaw = LookWaves(rng, 38 * kDegree, 3 * kDegree, 5 * kDegree);
  g.pitch = LookWaves(rng, 12 * kDegree, 3 * kDegree, 4 * kDegree);
  g.roll = LookWaves(rng, 8 * kDegree, 2 * kDegree, 3 * kDegree);
  return g;
}

// The device's attitude at time t (s from the start) over the path's heading, look-around scaled by k.
SO3 Attitude(const Gait& g, double heading, double t, double k) {
  const double r = k * Smoothstep7((t - kStandStill) / kRamp);
  return SO3::Exp(Eigen::Vector3d(0, 0, heading + r * Evaluate(g.yaw, t))) *
         SO3::Exp(Eigen::Vector3d(0, r * Evaluate(g.pitch, t), 0)) *
         SO3::Exp(Eigen::Vector3d(r * Evaluate(g.roll, t), 0, 0));
}

// The device's offset from the path point at time t (world frame), on a path pose heading along x_path.
Eigen::Vector3d Offset(const Gait& g, const SE3& path_pose, double t) {
  const double r = Smoothstep7((t - kStandStill) / kRamp);
  const double phi = 2.0 * kPi * g.step_hz * (t - kStandStill) + g.phase;
  const double bounce = g.bounce * std::sin(phi) + g.heel * std::sin(2.0 * phi + g.heel_phase);
  const double sway = g.sway * std::sin(0.5 * phi + g.sway_phase);
  return r * (sway * path_pose.rotation().col(1) + bounce * Eigen::Vector3d::UnitZ());
}

double Heading(const SE3& path_pose) {
  const Eigen::Matrix3d R = path_pose.rotation();
  return std::atan2(R(1, 0), R(0, 0));
}

// The attitudes along the path with look-around scale k, and their peak rate (central differences).
double PeakRate(const Gait& g, const Trajectory& path, double k, std::vector<SO3>* attitudes) {
  std::vector<SO3> R(path.size());
  for (std::size_t i = 0; i < path.size(); ++i)
    R[i] = Attitude(g, Heading(path.poses[i]), static_cast<double>(i) * kDt, k);
  double peak = 0.0;
  for (std::size_t i = 1; i + 1 < R.size(); ++i)
    peak = std::max(peak, (R[i - 1].inverse() * R[i + 1]).Log().norm() / (2.0 * kDt));
  if (attitudes != nullptr) *attitudes = std::move(R);
  return peak;
}

}  // namespace

Expected<HandheldTrajectory> HandheldSceneTrajectory(std::string_view scene, double duration_s,
                                                     std::uint64_t seed, Stamp start_stamp) {
  Expected<Trajectory> path =
      DefaultScenePath(scene, duration_s, seed, start_stamp, PathSpeed{kWalkingSpeed, kRamp, 0.04, 7.0});
  if (!path) return path.status();
  std::mt19937_64 rng(SubSeed(seed, std::string("handheld/") + std::string(scene)));
  const Gait gait = DrawGait(rng);

  // The look-around scale: peak(k) is close to linear in k (the path's own turns add a little), so the
  // fixed-point iteration converges in a few steps; it stops at the clamp for short sequences.
  const double target = kHandheldPeakRateDegS * kDegree;
  double k = 1.0;
  for (int iteration = 0; iteration < kScaleIterations; ++iteration) {
    const double peak = PeakRate(gait, *path, k, nullptr);
    const double next = std::clamp(peak > 0.0 ? k * target / peak : kMaxScale, kMinScale, kMaxScale);
    if (std::abs(next - k) <= 1e-6 * k) break;
    k = next;
  }
  HandheldTrajectory out;
  std::vector<SO3> attitudes;
  out.peak_rate_rad_s = PeakRate(gait, *path, k, &attitudes);
  out.look_scale = k;
  out.poses.stamps = path->stamps;
  out.poses.poses.reserve(path->size());
  for (std::size_t i = 0; i < path->size(); ++i) {
    const SE3& c = path->poses[i];
    out.poses.poses.emplace_back(attitudes[i],
                                 c.translation() + Offset(gait, c, static_cast<double>(i) * kDt));
  }
  out.path = std::move(*path);
  return out;
}

}  // namespace uf::sim
