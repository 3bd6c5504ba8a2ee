#include "odometry/estimator/init/short_window_map.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>

namespace uf::estimator {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The whitened linear system J x = y of step 2, with the three columns of g in place (gravity_column).
struct MapSystem {
  Eigen::MatrixXd J;
  Eigen::VectorXd y;
  int nodes = 0;
  int gravity_column = 0, bias_column = 0;
};

MapSystem BuildSystem(std::span<const SE3> poses, const std::vector<ImuPreintegration>& preintegrations,
                      double position_sigma_m, const InertialInitConfig& config) {
  MapSystem s;
  s.nodes = static_cast<int>(poses.size());
  const int n = s.nodes;
  const int v0 = 3 * n;  // first velocity column
  s.gravity_column = 6 * n;
  s.bias_column = 6 * n + 3;
  const int rows = 3 * n + 6 * (n - 1) + 3;
  s.J = Eigen::MatrixXd::Zero(rows, 6 * n + 6);
  s.y = Eigen::VectorXd::Zero(rows);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  int row = 0;
  for (int k = 0; k < n; ++k, row += 3) {  // LO positions
    s.J.block<3, 3>(row, 3 * k) = I / position_sigma_m;
    s.y.segment<3>(row) = poses[k].translation() / position_sigma_m;
  }
  for (int k = 0; k + 1 < n; ++k, row += 6) {  // IMU: rows [velocity; position]
    const ImuPreintegration& pre = preintegrations[static_cast<std::size_t>(k)];
    const double T = pre.sum_dt_seconds();
    const Eigen::Matrix3d R = poses[k].rotation();
    Eigen::Matrix<double, 6, Eigen::Dynamic> A =
        Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, s.J.cols());
    Eigen::Matrix<double, 6, 1> b;
    A.block<3, 3>(0, v0 + 3 * (k + 1)) = I;
    A.block<3, 3>(0, v0 + 3 * k) = -I;
    A.block<3, 3>(0, s.gravity_column) = -T * I;
    A.block<3, 3>(0, s.bias_column) = -R * pre.dv_dba();
    b.head<3>() = R * pre.delta_v();
    A.block<3, 3>(3, 3 * (k + 1)) = I;
    A.block<3, 3>(3, 3 * k) = -I;
    A.block<3, 3>(3, v0 + 3 * k) = -T * I;
    A.block<3, 3>(3, s.gravity_column) = -0.5 * T * T * I;
    A.block<3, 3>(3, s.bias_column) = -R * pre.dp_dba();
    b.tail<3>() = R * pre.delta_p();
    // Covariance of (dv, dp) in the world: blockdiag(R, R) Sigma blockdiag(R, R)^T; whitened by its Cholesky
    // factor (a tiny floor keeps a near-zero interval positive definite).
    Matrix6d rotate = Matrix6d::Zero();
    rotate.block<3, 3>(0, 0) = rotate.block<3, 3>(3, 3) = R;
    const Matrix6d sigma =
        rotate * pre.covariance().block<6, 6>(kImuVelocity, kImuVelocity) * rotate.transpose() +
        1e-12 * Matrix6d::Identity();
    const Eigen::LLT<Matrix6d> llt(sigma);
    s.J.middleRows(row, 6) = llt.matrixL().solve(A);
    s.y.segment<6>(row) = llt.matrixL().solve(b);
  }
  s.J.block<3, 3>(row, s.bias_column) = I / config.accel_bias_sigma;  // b_a prior about 0
  return s;
}

// An orthonormal basis (3x2) of the plane normal to the unit vector u.
Eigen::Matrix<double, 3, 2> TangentBasis(const Eigen::Vector3d& u) {
  const Eigen::Vector3d a = std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = u.cross(a).normalized();
  B.col(1) = u.cross(B.col(0));
  return B;
}

}  // namespace

Expected<InertialAlignment> ShortWindowMapAlignment(std::span<const SE3> poses,
                                                    std::vector<ImuPreintegration> preintegrations,
                                                    const InertialInitConfig& config) {
  if (poses.size() < 3 || preintegrations.size() + 1 != poses.size())
    return Status::Error("LiDAR-aided MAP: need >= 3 poses and one preintegration between each pair, got " +
                         std::to_string(poses.size()) + " and " + std::to_string(preintegrations.size()));
  const double gravity = preintegrations.front().params().gravity;
  for (ImuPreintegration& pre : preintegrations)
    pre.Repropagate(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::Vector3d gyro_bias = GyroBiasFromRotations(poses, preintegrations);
  if (!gyro_bias.allFinite()) return Status::Error("LiDAR-aided MAP: singular gyro bias system");
  for (ImuPreintegration& pre : preintegrations) pre.Repropagate(Eigen::Vector3d::Zero(), gyro_bias);

  // Step 2: g free, with the configured LO noise; then again with it scaled by the a posteriori factor
  // f = sqrt(RSS / redundancy) when the residuals say the LO is noisier (never below the configured value):
  // the LO's noise is not known in advance (2-4 mm between scans in the simulated streets, 1-4 cm on the
  // rough wild terrain, more for the scans registered against a map still smeared by a moving start's first
  // sweep). The LO rows carry the redundancy (the IMU rows are met almost exactly).
  double position_sigma = config.lidar_position_sigma_m;
  MapSystem s;
  Eigen::VectorXd x_free;
  for (int pass = 0; pass < 2; ++pass) {
    s = BuildSystem(poses, preintegrations, position_sigma, config);
    x_free = (s.J.transpose() * s.J).ldlt().solve(s.J.transpose() * s.y);
    if (!x_free.allFinite()) return Status::Error("LiDAR-aided MAP: singular alignment system");
    const double redundancy = static_cast<double>(s.J.rows() - s.J.cols());
    const double factor = redundancy > 0 ? std::sqrt((s.J * x_free - s.y).squaredNorm() / redundancy) : 1.0;
    if (factor <= 1 || pass == 1) break;
    position_sigma *= factor;
  }
  const Eigen::Vector3d g_free = x_free.segment<3>(s.gravity_column);
  if (g_free.norm() < 1e-9) return Status::Error("LiDAR-aided MAP: singular alignment system");

  // Step 3: |g| = gravity; g's columns replaced by the tilt d (2 columns).
  const int cols = static_cast<int>(s.J.cols()) - 1;
  Eigen::MatrixXd Jc(s.J.rows(), cols);
  Jc.leftCols(s.gravity_column) = s.J.leftCols(s.gravity_column);
  Jc.rightCols(3) = s.J.rightCols(3);  // b_a
  const Eigen::MatrixXd Jg = s.J.middleCols(s.gravity_column, 3);
  Eigen::Vector3d u = g_free.normalized();
  Eigen::VectorXd x;
  Eigen::MatrixXd H;
  for (int iteration = 0; iteration < 3; ++iteration) {
    const Eigen::Matrix<double, 3, 2> B = TangentBasis(u);
    Jc.middleCols(s.gravity_column, 2) = gravity * Jg * B;
    H = Jc.transpose() * Jc;
    x = H.ldlt().solve(Jc.transpose() * (s.y - gravity * Jg * u));
    if (!x.allFinite()) return Status::Error("LiDAR-aided MAP: singular system with |g| fixed");
    u = (u + B * x.segment<2>(s.gravity_column)).normalized();
  }
  // Step 4: the posterior covariance of the last solve.
  const Eigen::MatrixXd covariance = H.ldlt().solve(Eigen::MatrixXd::Identity(cols, cols));
  const Eigen::Matrix2d tilt = covariance.block<2, 2>(s.gravity_column, s.gravity_column);
  const int last_velocity = 3 * s.nodes + 3 * (s.nodes - 1);
  const Eigen::Matrix3d velocity = covariance.block<3, 3>(last_velocity, last_velocity);

  InertialAlignment alignment;
  alignment.mode = "lidar-aided";
  alignment.R_gravity_lo = AlignGravity(u);
  for (int k = 0; k < s.nodes; ++k)
    alignment.velocities.push_back(alignment.R_gravity_lo *
                                   Eigen::Vector3d(x.segment<3>(3 * s.nodes + 3 * k)));
  alignment.accel_bias = x.tail<3>();
  alignment.gyro_bias = gyro_bias;
  alignment.gravity_estimate = g_free.norm();
  alignment.tilt_sigma_rad =
      std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(tilt).eigenvalues().maxCoeff());
  alignment.position_sigma_m = position_sigma;
  alignment.velocity_sigma_mps =
      std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(velocity).eigenvalues().maxCoeff());
  return alignment;
}

}  // namespace uf::estimator
