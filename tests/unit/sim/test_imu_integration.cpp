// The self-consistency figure: integrating the simulated IMU with noise off reproduces the
// ground-truth trajectory to < 1 mm over 10 s, with the imu at the body origin and with a lever arm and a
// rotation offset.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "odometry/sim/imu_model.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

// Strapdown state of the imu frame in the world: orientation as an (unnormalised) quaternion, so that the
// whole state is a vector that classic RK4 can integrate to fourth order.
struct Strapdown {
  Quaterniond q;  // R_world_imu
  Vector3d v, p;  // world velocity and position of the imu, m/s and m
};

struct StrapdownRate {
  Eigen::Vector4d dq;
  Vector3d dv, dp;
};

// dq/dt = q (x) (0, omega) / 2, dv/dt = R(q) f + g_world, dp/dt = v.
StrapdownRate Rate(const Strapdown& s, const ImuSample& imu) {
  const Quaterniond omega(0.0, imu.gyro.x(), imu.gyro.y(), imu.gyro.z());
  return {0.5 * (s.q * omega).coeffs(), s.q.normalized() * imu.acc + Vector3d(0.0, 0.0, -kStandardGravity),
          s.v};
}

Strapdown Advance(const Strapdown& s, const StrapdownRate& rate, double dt) {
  return {Quaterniond(Eigen::Vector4d(s.q.coeffs() + dt * rate.dq)), s.v + dt * rate.dv, s.p + dt * rate.dp};
}

// One classic RK4 step of length h = t2 - t0 with the samples at its start, middle and end.
Strapdown Rk4Step(const Strapdown& s, const ImuSample& start, const ImuSample& middle, const ImuSample& end) {
  const double h = ToSeconds(end.stamp - start.stamp);
  const StrapdownRate k1 = Rate(s, start);
  const StrapdownRate k2 = Rate(Advance(s, k1, h / 2), middle);
  const StrapdownRate k3 = Rate(Advance(s, k2, h / 2), middle);
  const StrapdownRate k4 = Rate(Advance(s, k3, h), end);
  Strapdown next{Quaterniond(Eigen::Vector4d(s.q.coeffs() + h / 6 * (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq))),
                 s.v + h / 6 * (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv),
                 s.p + h / 6 * (k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp)};
  next.q.normalize();
  return next;
}

struct DeadReckoningErrors {
  double position = 0;  // m
  double rotation = 0;  // rad
  double velocity = 0;  // m/s
};

// Integrates 200 Hz noise-free samples over 10 s (RK4 steps of 10 ms) from the true state at the first one,
// and returns the largest deviation from the true imu trajectory at the step ends.
DeadReckoningErrors DeadReckon(const TrajectorySpline& trajectory, const SE3& T_body_imu) {
  const Expected<ImuSimulator> simulator = ImuSimulator::Create(trajectory, T_body_imu, 200.0, ImuNoise{}, 1);
  EXPECT_TRUE(simulator.ok()) << simulator.error();
  const Stamp begin = trajectory.begin() + kNanosecondsPerSecond;
  const Expected<SimulatedImu> imu = simulator->Generate(begin, begin + 10 * kNanosecondsPerSecond);
  EXPECT_TRUE(imu.ok()) << imu.error();
  const ImuKinematics start = simulator->Kinematics(begin);
  Strapdown state{start.T_world_imu.so3().quaternion(), start.velocity_world,
                  start.T_world_imu.translation()};
  DeadReckoningErrors errors;
  for (std::size_t k = 0; k + 2 < imu->samples.size(); k += 2) {
    state = Rk4Step(state, imu->samples[k], imu->samples[k + 1], imu->samples[k + 2]);
    const ImuKinematics truth = simulator->Kinematics(imu->samples[k + 2].stamp);
    errors.position = std::max(errors.position, (state.p - truth.T_world_imu.translation()).norm());
    errors.velocity = std::max(errors.velocity, (state.v - truth.velocity_world).norm());
    errors.rotation = std::max(errors.rotation, (truth.T_world_imu.so3().inverse() * SO3(state.q)).angle());
  }
  EXPECT_EQ(imu->samples.back().stamp, begin + 10 * kNanosecondsPerSecond);
  return errors;
}

// The imu at the body origin, and mounted with a 0.4 m lever arm and a 2.1 rad rotation offset.
const std::pair<const char*, SE3> kMounts[] = {
    {"origin", SE3()},
    {"offset", SE3(SO3::Exp(Vector3d(0.1, -0.3, 2.0)), Vector3d(0.3, -0.15, 0.2))},
};

void Record(const std::string& mount, const DeadReckoningErrors& errors) {
  test::RecordFigure(mount + "_max_position_error_m", errors.position);
  test::RecordFigure(mount + "_max_rotation_error_rad", errors.rotation);
  test::RecordFigure(mount + "_max_velocity_error_m_s", errors.velocity);
}

// A trajectory as a user gives it: poses of a drive at 100 Hz, resampled by the spline (50 ms knots).
TrajectorySpline ResampledDrive() {
  const Trajectory poses = test::SampleSmoothTrajectory(1'000'000'000, 12.0, 100.0);
  return TrajectorySpline::FitPoses(poses, 50'000'000).value();
}

TEST(ImuIntegrationTest, NoiseFreeImuReproducesGroundTruthOnADrive) {
  // Measured: 1.3e-8 m, 3.7e-8 rad (origin); 2.5e-7 m, 3.0e-8 rad (offset).
  for (const auto& [mount, T_body_imu] : kMounts) {
    const DeadReckoningErrors errors = DeadReckon(ResampledDrive(), T_body_imu);
    Record(mount, errors);
    EXPECT_LT(errors.position, 1e-3) << mount;
    EXPECT_LT(errors.velocity, 1e-4);
    EXPECT_LT(errors.rotation, 1e-6);
  }
}

TEST(ImuIntegrationTest, NoiseFreeImuReproducesGroundTruthOnBriskMotion) {
  // Random control points every 0.1 s: ~3 m/s, ~2.5 rad/s about changing axes, ~40 rad/s^2.
  // Measured: 9.9e-5 m, 1.9e-7 rad (origin); 1.1e-4 m, 1.9e-7 rad (offset).
  const TrajectorySpline brisk = test::RandomSpline(5, 115, 100'000'000);
  for (const auto& [mount, T_body_imu] : kMounts) {
    const DeadReckoningErrors errors = DeadReckon(brisk, T_body_imu);
    Record(mount, errors);
    EXPECT_LT(errors.position, 1e-3) << mount;
    EXPECT_LT(errors.velocity, 1e-3);
    EXPECT_LT(errors.rotation, 1e-5);
  }
}

}  // namespace
}  // namespace uf
