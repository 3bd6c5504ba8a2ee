#include "odometry/sim/imu_model.h"

#include <cassert>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "odometry/sim/sampling.h"

namespace uf {
namespace {

using sim::NumberText;

Status CheckNonNegative(const std::string& name, double value) {
  if (std::isfinite(value) && value >= 0.0) return Status();
  return Status::Error("imu " + name + " must be finite and >= 0, got " + NumberText(value));
}

// Standard normal numbers from std::mt19937_64 by the Box-Muller transform, written out because
// std::normal_distribution is implementation-defined: this way a seed gives the same samples with every
// standard library.
class StandardNormal {
 public:
  explicit StandardNormal(std::uint64_t seed) : engine_(seed) {}

  double Next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    // Two uniforms from the top 53 bits; u1 in (0, 1] keeps the logarithm finite.
    const double u1 = static_cast<double>((engine_() >> 11) + 1) * 0x1.0p-53;
    const double u2 = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
    const double radius = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * std::numbers::pi * u2;
    spare_ = radius * std::sin(angle);
    has_spare_ = true;
    return radius * std::cos(angle);
  }

  Eigen::Vector3d NextVector() {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v(i) = Next();  // in order: x, y, z
    return v;
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Each axis clamped to [-limit, limit]; limit 0 means no saturation.
Eigen::Vector3d Saturate(const Eigen::Vector3d& v, double limit) {
  if (limit <= 0.0) return v;
  return v.cwiseMax(-limit).cwiseMin(limit);
}

}  // namespace

Expected<ImuSimulator> ImuSimulator::Create(TrajectorySpline trajectory, const SE3& T_body_imu,
                                            double rate_hz, const ImuNoise& noise, std::uint64_t seed,
                                            double gravity) {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0 || rate_hz > 1e9) {
    return Status::Error("imu rate must be > 0 Hz and at most 1e9 Hz (one sample per ns), got " +
                         NumberText(rate_hz));
  }
  const std::pair<const char*, double> non_negative[] = {
      {"accel_noise_density", noise.accel_noise_density},
      {"gyro_noise_density", noise.gyro_noise_density},
      {"accel_bias_random_walk", noise.accel_bias_random_walk},
      {"gyro_bias_random_walk", noise.gyro_bias_random_walk},
      {"accel_saturation", noise.accel_saturation},
      {"gyro_saturation", noise.gyro_saturation},
      {"gravity", gravity},
  };
  for (const auto& [name, value] : non_negative) {
    if (Status status = CheckNonNegative(name, value); !status.ok()) return status;
  }
  if (!noise.initial_accel_bias.allFinite() || !noise.initial_gyro_bias.allFinite()) {
    return Status::Error("imu initial biases must be finite");
  }
  if (!T_body_imu.matrix().allFinite()) return Status::Error("imu extrinsic T_body_imu must be finite");
  return ImuSimulator(std::move(trajectory), T_body_imu, rate_hz, noise, seed, gravity);
}

ImuSimulator::ImuSimulator(TrajectorySpline trajectory, const SE3& T_body_imu, double rate_hz,
                           const ImuNoise& noise, std::uint64_t seed, double gravity)
    : trajectory_(std::move(trajectory)),
      T_body_imu_(T_body_imu),
      rate_hz_(rate_hz),
      noise_(noise),
      seed_(seed),
      gravity_(gravity) {}

ImuKinematics ImuSimulator::Kinematics(Stamp t) const {
  const TrajectorySpline::State body = trajectory_.Evaluate(t);
  const Eigen::Matrix3d& R_world_body = body.T_world_body.rotation();
  const Eigen::Vector3d& lever_arm = T_body_imu_.translation();
  const Eigen::Vector3d& omega = body.angular_velocity_body;
  const Eigen::Vector3d& alpha = body.angular_acceleration_body;
  // Differentiating p_imu = p_body + R r twice with dR/dt = R Hat(omega): R (omega x r), then
  // R (alpha x r + omega x (omega x r)).
  ImuKinematics imu;
  imu.T_world_imu = body.T_world_body * T_body_imu_;
  imu.velocity_world = body.velocity_world + R_world_body * omega.cross(lever_arm);
  imu.acceleration_world =
      body.acceleration_world + R_world_body * (alpha.cross(lever_arm) + omega.cross(omega.cross(lever_arm)));
  imu.angular_velocity_imu = T_body_imu_.rotation().transpose() * omega;
  return imu;
}

ImuSample ImuSimulator::IdealSample(Stamp t) const {
  const ImuKinematics imu = Kinematics(t);
  ImuSample sample;
  sample.stamp = t;
  // Specific force: acceleration minus gravity, g_world = (0, 0, -gravity), in the imu frame.
  sample.acc =
      imu.T_world_imu.rotation().transpose() * (imu.acceleration_world + Eigen::Vector3d(0.0, 0.0, gravity_));
  sample.gyro = imu.angular_velocity_imu;
  return sample;
}

Expected<SimulatedImu> ImuSimulator::Generate(Stamp begin, Stamp end) const {
  if (Status s = sim::CheckSampleInterval("imu", trajectory_, begin, end, rate_hz_); !s.ok()) return s;
  const long double period_ns = 1e9L / static_cast<long double>(rate_hz_);
  const Stamp span = end - begin;
  const auto inside = [&](std::int64_t k) { return static_cast<long double>(k) * period_ns < span + 0.5L; };
  auto count = static_cast<std::int64_t>(std::ceil((span + 0.5L) / period_ns));  // k = 0 .. count - 1
  while (count > 1 && !inside(count - 1)) --count;  // whatever the rounding of the division
  while (inside(count)) ++count;

  // Discrete standard deviations (see the header): white noise sigma * sqrt(rate), random-walk steps
  // sigma_b * sqrt(dt).
  const double sqrt_rate = std::sqrt(rate_hz_);
  const double accel_white = noise_.accel_noise_density * sqrt_rate;
  const double gyro_white = noise_.gyro_noise_density * sqrt_rate;
  const double accel_walk = noise_.accel_bias_random_walk / sqrt_rate;
  const double gyro_walk = noise_.gyro_bias_random_walk / sqrt_rate;

  StandardNormal normal(seed_);
  ImuBiases bias{noise_.initial_accel_bias, noise_.initial_gyro_bias};
  SimulatedImu out;
  out.samples.reserve(static_cast<std::size_t>(count));
  out.biases.reserve(static_cast<std::size_t>(count));
  for (std::int64_t k = 0; k < count; ++k) {
    // Each stamp rounded on its own, so a period that is not a whole number of ns does not drift.
    const Stamp stamp = sim::GridStamp(begin, period_ns, k);
    ImuSample sample = IdealSample(stamp);
    // Draws in a fixed order (accel noise, gyro noise, accel walk, gyro walk), even for zero densities, so
    // switching one noise source on or off leaves the others' sequences unchanged.
    sample.acc =
        Saturate(sample.acc + bias.accel + accel_white * normal.NextVector(), noise_.accel_saturation);
    sample.gyro =
        Saturate(sample.gyro + bias.gyro + gyro_white * normal.NextVector(), noise_.gyro_saturation);
    out.samples.push_back(sample);
    out.biases.push_back(bias);
    bias.accel += accel_walk * normal.NextVector();
    bias.gyro += gyro_walk * normal.NextVector();
  }
  return out;
}

}  // namespace uf
