// The IMU samples a sliding window still needs, and the preintegration between two of its nodes over them
// (imu_preintegration.h), shared by the LiDAR-inertial and the wheel-inertial windows. Samples are screened
// on arrival (finite, stamps increasing); an interval with a step between samples longer than max_gap_s is
// refused rather than integrated across (the midpoint rule would treat the gap as one constant-rate step).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/imu_noise_params.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/measurements.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::estimator {

class ImuBuffer {
 public:
  // params must validate (asserted by the preintegration); max_gap_s > 0.
  ImuBuffer(const ImuNoiseParams& params, double max_gap_s);

  // Keeps a sample; a non-finite or not-increasing one is skipped and the reason returned (a warning).
  std::optional<std::string> Add(const ImuSample& sample);
  bool empty() const { return samples_.empty(); }
  Stamp CoveredUntil() const;  // the last sample's stamp; min when none
  Stamp OldestStamp() const;   // the first sample kept; max when none

  // The preintegration over [from, to] at the biases (accel_bias, gyro_bias); an error when the samples do
  // not cover the interval or leave a gap longer than max_gap_s in it.
  Expected<ImuPreintegration> Preintegrate(Stamp from, Stamp to, const Eigen::Vector3d& accel_bias,
                                           const Eigen::Vector3d& gyro_bias) const;
  // The same at the biases of a speed_bias block [v, b_a, b_g] (state/nav_state.h); null: zero biases.
  Expected<ImuPreintegration> Preintegrate(Stamp from, Stamp to, const double* speed_bias) const;
  // The world's gravity the preintegrations get (ImuPreintegration::SetGravityWorld); (0, 0, -gravity)
  // until set.
  void SetGravityWorld(const Eigen::Vector3d& g) { gravity_world_ = g; }
  // The samples with from <= stamp <= to.
  std::vector<ImuSample> Between(Stamp from, Stamp to) const;
  // Drops the samples no interval from `oldest` on needs (one before it is kept).
  void Trim(Stamp oldest);

 private:
  ImuNoiseParams params_;
  Eigen::Vector3d gravity_world_;
  Stamp max_gap_;
  std::vector<ImuSample> samples_;  // increasing stamps
};

}  // namespace uf::estimator
