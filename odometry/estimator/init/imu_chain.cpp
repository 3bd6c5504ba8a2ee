#include "odometry/estimator/init/imu_chain.h"

namespace uf::estimator {

// R_k+1 = R_k dR_k, a_k+1 = a_k + b_k T_k + R_k dp_k, b_k+1 = b_k + R_k dv_k. With R_k(b + d) ~= R_k
// Exp(J_k d) and dR_k(b + d) ~= dR_k Exp(Jr_k d) (the preintegration's dR/dbg):
// R_k+1(b + d) ~= R_k dR_k Exp(dR_k^T J_k d) Exp(Jr_k d), so J_k+1 = dR_k^T J_k + Jr_k.
ImuChain ChainPreintegrations(std::span<const ImuPreintegration> preintegrations,
                              const Eigen::Vector3d& gyro_bias) {
  ImuChain chain{
      {SO3()}, {Eigen::Vector3d::Zero()}, {Eigen::Vector3d::Zero()}, {0.0}, {Eigen::Matrix3d::Zero()}};
  for (const ImuPreintegration& pre : preintegrations) {
    const double T = pre.sum_dt_seconds();
    const SO3 R = chain.R.back();
    const SO3 dR = pre.CorrectedDeltaR(gyro_bias);
    chain.a.push_back(chain.a.back() + chain.b.back() * T +
                      R * pre.CorrectedDeltaP(pre.accel_bias(), gyro_bias));
    chain.b.push_back(chain.b.back() + R * pre.CorrectedDeltaV(pre.accel_bias(), gyro_bias));
    chain.R.push_back(R * dR);
    chain.dR_dbg.push_back(dR.inverse().matrix() * chain.dR_dbg.back() + pre.dR_dbg());
    chain.t.push_back(chain.t.back() + T);
  }
  return chain;
}

}  // namespace uf::estimator
