// The wheel odometry's part of the window (docs/METHOD.md "Wheel factor"): it keeps the wheel samples, owns
// the wheel scale block (shared by every wheel factor, with its prior), and links two nodes by a wheel
// factor over the samples between their stamps. Used by the LiDAR odometry's window (LWIO, LWGIO); nothing
// in it depends on the LiDAR.
#pragma once

#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/wheel_factor_config.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/estimator/preintegration/wheel_preintegration.h"
#include "odometry/estimator/providers/sensor_factor_stats.h"
#include "odometry/estimator/schedule/activation_gate.h"
#include "odometry/estimator/window/factor_graph.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

// What the IMU says of a node interval, for the wheel's scheduling: nothing (the node was not its
// prediction), its prediction from clipped readings (not scored against, and the next ones only once the
// window has settled), or its prediction (scored against).
enum class WheelReference { kNone, kClipped, kPredicted };

// The reference of an interval whose node the IMU predicted with `imu` (null: it did not).
inline WheelReference WheelReferenceOf(const ImuPreintegration* imu) {
  if (imu == nullptr) return WheelReference::kNone;
  return imu->clipped_steps() > 0 ? WheelReference::kClipped : WheelReference::kPredicted;
}

class WheelProvider {
 public:
  // T_body_wheel: the wheel (base) frame in the window's body frame (the IMU in LIO).
  WheelProvider(const WheelFactorConfig& config, const SE3& T_body_wheel);
  WheelProvider(const WheelProvider&) = delete;  // the graph refers to scale_
  WheelProvider& operator=(const WheelProvider&) = delete;

  // Keeps a sample; a non-finite or not-increasing one is skipped and the reason returned (a warning).
  std::optional<std::string> Add(const WheelSample& sample);
  // The last sample's time on the estimator's clock (config.time_offset_s applied); min when none.
  Stamp CoveredUntil() const;

  // Registers the scale block with the graph, with its prior (again after the graph was cleared).
  void Attach(FactorGraph& graph);
  // Adds the wheel factor between the poses at `from` and `to` (tagged `tag`); an error, and no factor,
  // when the samples do not cover the interval (see WheelPreintegration::Between). With scheduling
  // (config.schedule) and `reference` kPredicted (pose_to holds the IMU's prediction from pose_from, a
  // reference the wheel has not shaped, from readings none of which was clipped), the interval is scored
  // first (ScoreWheelMotion) and its factor left out while the gate is shut (its speed tolerance growing with
  // the time shut, config.schedule); the score is kept for TakeConsistency. speed_bias_from / _to (the nodes'
  // velocity and bias blocks; may be null) give the IMU's velocity change over the interval, which the
  // score's change window compares with the wheel's.
  Status Link(FactorGraph& graph, long tag, double* pose_from, double* pose_to, Stamp from, Stamp to,
              WheelReference reference = WheelReference::kNone, const double* speed_bias_from = nullptr,
              const double* speed_bias_to = nullptr);
  // The score of the interval tagged `tag`, if it was scored; scores of earlier tags are dropped.
  std::optional<WheelConsistency> TakeConsistency(long tag);
  // The body's motion over [from, to] dead-reckoned from the wheel alone at unit scale,
  // T_body(from)^-1 T_body(to) = T_body_wheel dT_wheel T_body_wheel^-1 (dT_wheel: the preintegrated
  // motion); an error when the samples do not cover the interval. For an initialization without the window.
  Expected<SE3> Motion(Stamp from, Stamp to) const;
  // Whether the wheels read no motion over [from, to] (estimator clock): every sample from the last at or
  // before `from` to the first at or after `to` within kRestSpeed / kRestTurnRate of zero. False when the
  // samples do not cover the interval.
  bool AtRest(Stamp from, Stamp to) const;
  // The information (1/m^2, world) the wheel factor's noise gives the body's position over an interval of dt
  // seconds, the body at attitude R_world_body: a velocity density q gives the position a variance q^2 dt,
  // the forward speed's along the wheel's x axis, the non-holonomic terms' across it.
  Eigen::Matrix3d PositionInformation(const SO3& R_world_body, double dt) const;
  // The stationary branch (config.stationary_updates): where the wheels are AtRest over [from, to], adds
  // the zero-motion factor (factors/zero_motion_factor.h) on the two nodes' poses and velocities (tagged
  // `tag`, kind kWheel) and returns true.
  bool LinkAtRest(FactorGraph& graph, long tag, double* pose_from, double* pose_to, double* speed_bias_from,
                  double* speed_bias_to, Stamp from, Stamp to);
  static constexpr double kRestSpeed = 1e-3;     // m/s
  static constexpr double kRestTurnRate = 1e-3;  // rad/s
  // Drops the samples no interval from `oldest` on needs (one before it is kept).
  void Trim(Stamp oldest);

  double* scale_block() { return &scale_; }
  bool scale_free() const { return config_.estimate_scale; }
  // Its part of the window's report: factors added, skipped and suppressed by the schedule, the scale.
  void Report(SensorFactorStats& stats) const;

 private:
  // Whether the interval's factor may join: scores it and updates the gate (true without scheduling).
  bool Admit(long tag, const WheelPreintegration& pre, const double* pose_from, const double* pose_to,
             Stamp from, Stamp to, const double* speed_bias_from, const double* speed_bias_to);
  // c of ScoreWheelMotion: the interval's (wheel - IMU) velocity change joins those of the last
  // change_window_s; the norm of their sum in the wheel's plane at `to` (0 without velocities).
  double SpeedChangeDisagreement(const SE3& T_from, const SE3& T_to, Stamp from, Stamp to,
                                 const double* speed_bias_from, const double* speed_bias_to);
  // The body's velocity (world) by the wheel sample nearest `t` (estimator clock), at the current scale:
  // v_body = v_wheel - w x t_body_wheel, turned by the body's attitude. None without samples.
  std::optional<Eigen::Vector3d> WheelVelocity(Stamp t, const SO3& R_world_body) const;

  WheelFactorConfig config_;
  SE3 T_body_wheel_;
  std::vector<WheelSample> samples_;  // wheel clock, increasing
  double scale_ = 1.0;
  int added_ = 0, skipped_ = 0, suppressed_ = 0, at_rest_ = 0;
  ActivationGate gate_;
  std::optional<Stamp> shut_at_;                        // when the gate last shut
  Eigen::Vector2d baseline_ = Eigen::Vector2d::Zero();  // u_0 (schedule/wheel_consistency.h), m/s
  std::map<long, WheelConsistency> scores_;             // by tag, until taken
  std::deque<std::pair<Stamp, Eigen::Vector3d>> changes_;  // (interval end, its velocity-change disagreement)
  // The end of the last interval whose IMU readings were clipped: the IMU's prediction carries that
  // interval's error for a while, so scoring resumes change_window_s after it, the first scored interval
  // restarting u_0 and the change window.
  std::optional<Stamp> clipped_at_;
  // The start of the first interval the IMU predicted (the inertial initialization): its prediction rests
  // on a velocity and biases nothing has confirmed yet, so scoring starts change_window_s later, like after
  // a clipped interval.
  std::optional<Stamp> predicted_from_;
  bool restart_baseline_ = false;
};

}  // namespace uf::estimator
