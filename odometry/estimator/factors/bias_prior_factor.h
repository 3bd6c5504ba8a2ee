// A prior on the IMU biases of one node (speed_bias block, nav_state.h layout [v, b_a, b_g]):
//   r = [ (b_a - b_a0) / sigma_accel ;  (b_g - b_g0) / sigma_gyro ]   (6; the velocity is left alone)
// What it holds: while the vehicle does not turn, a tilt of the body by d (roll or pitch) and an
// accelerometer bias b = g x d leave every IMU residual unchanged (the bias cancels the tilted gravity),
// so without a LiDAR or camera to fix the attitude only the bias's own prior bounds the pair. The sigmas are
// the IMU's turn-on bias uncertainty (datasheet), about the alignment's estimate.
//
// Jacobians by Ceres automatic differentiation.
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <memory>

namespace uf::estimator {

// sigmas finite and > 0 (asserted). One block: speed_bias (9).
std::unique_ptr<ceres::CostFunction> MakeBiasPriorFactor(const Eigen::Vector3d& accel_bias,
                                                         const Eigen::Vector3d& gyro_bias, double sigma_accel,
                                                         double sigma_gyro);

}  // namespace uf::estimator
