// What the IMU alone says about the nodes of an initialization window (docs/METHOD.md "Visual-inertial
// odometry", mode D): the preintegrations between consecutive nodes chained from node 0, at a given gyro
// bias (the accelerometer's taken as 0).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/so3.h"

namespace uf::estimator {

// Node k's rotation R_k from node 0 (R_0 = I); a_k, the position it would have from rest without gravity;
// b_k, the velocity it would have gained; t_k, its time since node 0 (s); and dR_dbg_k, how R_k turns with
// the gyro bias: R_k(b_g + d) ~= R_k Exp(dR_dbg_k d).
struct ImuChain {
  std::vector<SO3> R;
  std::vector<Eigen::Vector3d> a, b;
  std::vector<double> t;
  std::vector<Eigen::Matrix3d> dR_dbg;
};

// preintegrations[k] between nodes k and k + 1, corrected to gyro_bias to first order.
ImuChain ChainPreintegrations(std::span<const ImuPreintegration> preintegrations,
                              const Eigen::Vector3d& gyro_bias);

}  // namespace uf::estimator
