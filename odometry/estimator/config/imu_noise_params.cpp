#include "odometry/estimator/config/imu_noise_params.h"

#include <cmath>
#include <string>

namespace uf::estimator {
namespace {

Status Positive(const char* field, double value) {
  if (std::isfinite(value) && value > 0.0) return Status();
  return Status::Error(std::string("imu.") + field + ": must be finite and > 0, got " +
                       std::to_string(value));
}

}  // namespace

Status ValidateImuNoiseParams(const ImuNoiseParams& params) {
  for (const auto& [field, value] : {std::pair{"accel_noise_density", params.accel_noise_density},
                                     std::pair{"gyro_noise_density", params.gyro_noise_density},
                                     std::pair{"accel_bias_random_walk", params.accel_bias_random_walk},
                                     std::pair{"gyro_bias_random_walk", params.gyro_bias_random_walk},
                                     std::pair{"max_accel_bias_change", params.max_accel_bias_change},
                                     std::pair{"max_gyro_bias_change", params.max_gyro_bias_change}}) {
    if (Status status = Positive(field, value); !status.ok()) return status;
  }
  for (const auto& [field, value] :
       {std::pair{"gravity", params.gravity}, std::pair{"gyro_range", params.gyro_range},
        std::pair{"accel_range", params.accel_range}}) {
    if (!std::isfinite(value) || value < 0.0)
      return Status::Error(std::string("imu.") + field + ": must be finite and >= 0, got " +
                           std::to_string(value));
  }
  return Status();
}

}  // namespace uf::estimator
