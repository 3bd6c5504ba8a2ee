#include "odometry/estimator/init/inertial_alignment.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "odometry/estimator/init/init_mode_selection.h"

namespace uf::estimator {

SO3 AlignGravity(const Eigen::Vector3d& g_lo) {
  return SO3(Eigen::Quaterniond::FromTwoVectors(g_lo.normalized(), Eigen::Vector3d(0, 0, -1)));
}

Eigen::Vector3d GyroBiasFromRotations(std::span<const SE3> poses,
                                      const std::vector<ImuPreintegration>& preintegrations) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < preintegrations.size(); ++k) {
    const ImuPreintegration& pre = preintegrations[k];
    const Eigen::Matrix3d J = pre.dR_dbg();
    const SO3 relative = poses[k].so3().inverse() * poses[k + 1].so3();
    const Eigen::Vector3d e = (pre.delta_R().inverse() * relative).Log();
    A += J.transpose() * J;
    b += J.transpose() * e;
  }
  return A.ldlt().solve(b);
}

namespace {

// Steps 2 and 4 of M: least squares for x = [v_0 .. v_n, g] (or only the velocities when g is given).
Eigen::VectorXd SolveVelocitiesAndGravity(std::span<const SE3> poses,
                                          const std::vector<ImuPreintegration>& preintegrations,
                                          const Eigen::Vector3d* fixed_gravity) {
  const int nodes = static_cast<int>(poses.size());
  const int unknowns = 3 * nodes + (fixed_gravity ? 0 : 3);
  const int rows = 6 * static_cast<int>(preintegrations.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, unknowns);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(rows);
  for (int k = 0; k + 1 < nodes; ++k) {
    const ImuPreintegration& pre = preintegrations[static_cast<std::size_t>(k)];
    const double T = pre.sum_dt_seconds();
    const Eigen::Matrix3d R = poses[k].rotation();
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const int row = 6 * k;
    // Position: -T v_k - T^2/2 g = R_k dp_k - (p_k+1 - p_k).
    A.block<3, 3>(row, 3 * k) = -T * I;
    b.segment<3>(row) = R * pre.delta_p() - (poses[k + 1].translation() - poses[k].translation());
    // Velocity: v_k+1 - v_k - T g = R_k dv_k.
    A.block<3, 3>(row + 3, 3 * k) = -I;
    A.block<3, 3>(row + 3, 3 * (k + 1)) = I;
    b.segment<3>(row + 3) = R * pre.delta_v();
    if (fixed_gravity) {
      b.segment<3>(row) += 0.5 * T * T * *fixed_gravity;
      b.segment<3>(row + 3) += T * *fixed_gravity;
    } else {
      A.block<3, 3>(row, 3 * nodes) = -0.5 * T * T * I;
      A.block<3, 3>(row + 3, 3 * nodes) = -T * I;
    }
  }
  return A.colPivHouseholderQr().solve(b);
}

}  // namespace

Expected<InertialAlignment> StaticAlignment(const InitIndicators& in, std::span<const SE3> poses,
                                            const InertialInitConfig& config, double gravity) {
  if (const std::string why = NotStaticReason(in, config, gravity); !why.empty())
    return Status::Error("static initialization: not static: " + why);
  const Eigen::Vector3d& mean_acc = in.mean_acc;

  // At rest the specific force is -g in the imu frame: R_lo_imu0 mean_acc points along +z of the aligned
  // world, i.e. g_lo = -R_lo_imu0 mean_acc.
  InertialAlignment alignment;
  alignment.mode = "static";
  alignment.R_gravity_lo = AlignGravity(-(poses.front().rotation() * mean_acc));
  alignment.velocities.assign(poses.size(), Eigen::Vector3d::Zero());
  alignment.gyro_bias = in.mean_gyro;
  alignment.gravity_estimate = mean_acc.norm();
  return alignment;
}

Expected<InertialAlignment> LidarAidedAlignment(std::span<const SE3> poses,
                                                std::vector<ImuPreintegration> preintegrations,
                                                const InertialInitConfig& config) {
  if (poses.size() < 3 || preintegrations.size() + 1 != poses.size())
    return Status::Error(
        "LiDAR-aided initialization: need >= 3 poses and one preintegration between each "
        "pair, got " +
        std::to_string(poses.size()) + " and " + std::to_string(preintegrations.size()));
  const double gravity = preintegrations.front().params().gravity;
  for (ImuPreintegration& pre : preintegrations)
    pre.Repropagate(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::Vector3d gyro_bias = GyroBiasFromRotations(poses, preintegrations);
  for (ImuPreintegration& pre : preintegrations) pre.Repropagate(Eigen::Vector3d::Zero(), gyro_bias);

  const Eigen::VectorXd x = SolveVelocitiesAndGravity(poses, preintegrations, nullptr);
  const Eigen::Vector3d g = x.tail<3>();
  if (!x.allFinite() || !gyro_bias.allFinite())
    return Status::Error("LiDAR-aided initialization: singular alignment system");
  if (std::abs(g.norm() - gravity) > config.max_gravity_error * gravity) {
    std::ostringstream why;
    why << "LiDAR-aided initialization: estimated gravity " << g.norm() << " m/s^2 is not within "
        << config.max_gravity_error * 100 << " % of " << gravity << " (too little excitation or a bad "
        << "LiDAR solution)";
    return Status::Error(why.str());
  }
  const Eigen::Vector3d g_fixed = g.normalized() * gravity;
  const Eigen::VectorXd v = SolveVelocitiesAndGravity(poses, preintegrations, &g_fixed);

  InertialAlignment alignment;
  alignment.mode = "lidar-aided";
  alignment.R_gravity_lo = AlignGravity(g_fixed);
  for (std::size_t k = 0; k < poses.size(); ++k)
    alignment.velocities.push_back(alignment.R_gravity_lo * Eigen::Vector3d(v.segment<3>(3 * k)));
  alignment.gyro_bias = gyro_bias;
  alignment.gravity_estimate = g.norm();
  return alignment;
}

Expected<InertialAlignment> AlignStaticOrMoving(const ImuBuffer& imu, std::span<const Stamp> stamps,
                                                std::span<const SE3> poses, const InertialInitConfig& config,
                                                double gravity, bool allow_moving) {
  const std::vector<ImuSample> samples = imu.Between(stamps.front(), stamps.back());
  const InitIndicators indicators = ComputeInitIndicators(samples, stamps, poses, 0.0, gravity);
  Expected<InertialAlignment> alignment = StaticAlignment(indicators, poses, config, gravity);
  if (alignment) return alignment;
  const std::string static_failure = alignment.status().message();
  if (!allow_moving)
    return Status::Error(
        static_failure +
        "; no moving start without the wheel's poses (the visual-inertial start runs once the "
        "camera sees the motion)");
  std::vector<ImuPreintegration> preintegrations;
  for (std::size_t k = 1; k < stamps.size(); ++k) {
    Expected<ImuPreintegration> pre = imu.Preintegrate(stamps[k - 1], stamps[k], nullptr);
    if (!pre) return Status::Error(static_failure + "; " + pre.status().message());
    preintegrations.push_back(std::move(*pre));
  }
  alignment = LidarAidedAlignment(poses, std::move(preintegrations), config);
  if (!alignment) return Status::Error(static_failure + "; " + alignment.status().message());
  return alignment;
}

}  // namespace uf::estimator
