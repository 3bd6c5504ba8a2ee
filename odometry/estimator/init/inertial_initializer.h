// The observability-aware initialization of LIO as a sequence of attempts (docs/METHOD.md
// "Observability-aware initialization"; paper Sec. III-C, Algorithm 1): with each new scan the initialization
// window is measured (init_mode_selection.h), a mode chosen (S, M or A), S or M solved (inertial_alignment.h,
// short_window_map.h) and admitted only after the check of init_admission.h.
//
// The initialization window: the scans of the odometry window (their poses as solved now) and, before them,
// the scans that already left it (their last poses), up to max_scans scans, with a copy of the IMU samples
// they need: M's gravity sharpens with the square of the span, so it may need more than the odometry window
// holds. The modes work on the scans' middles, where a registration places a scan best
// (init_mode_selection.h); the admitted state is given at the odometry window's nodes. A local-map restart
// (no scan in common with the previous attempt's) starts the window again.
//
// Attempts are bounded by the data: one per scan, each O(max_scans^3) at most. A deferral waits for the next
// scan with a longer window; a rejection also drops the window's oldest scan while more than min_scans
// remain: a transient that spoiled the window leaves it, and a shorter window grows instead. An IMU gap in
// the window (the preintegration refuses it) defers, and the window starts again after the gap. The first
// deferral and the first rejection of an initialization are returned as warnings; all are counted in the
// record, and the first few rejection reasons kept.
//
// Velocities: those of the modes are at the scans' middles; each node's comes from the latest middle before
// it through the IMU, v(t) = v_m + g (t - t_m) + R_m dv(t_m, t) (before the first middle, backwards from it).
//
// Latency: from the first IMU sample of the initialization (after a re-initialization: the restart) to the
// newest node of the admitted window, in stream time.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "odometry/estimator/config/imu_noise_params.h"
#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/init/inertial_alignment.h"
#include "odometry/estimator/init/init_admission.h"
#include "odometry/estimator/init/init_mode_selection.h"
#include "odometry/estimator/preintegration/imu_buffer.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"

namespace uf::estimator {

// One scan of the odometry window, as the initialization sees it.
struct InitScan {
  long id = 0;              // increasing
  Stamp begin = 0;          // its begin node (the sweep's start; the first scan of a map: its middle)
  Stamp middle = 0;         // halfway between its begin and end nodes
  SE3 pose;                 // T_lo_imu there (between the begin and end node poses)
  bool registered = false;  // registered against the map (or the first of a map): its pose is measured
};

// What the odometry window hands each attempt: its scans (oldest first) and its nodes.
struct InitWindow {
  std::vector<InitScan> scans;
  std::vector<Stamp> node_stamps;
  std::vector<SE3> node_poses;  // T_lo_imu
  // Whether the wheels read no motion over [from, to] (null without wheels, or with the stationary branch
  // off): S then takes the platform for at rest whatever speed the LO poses show, which is their noise (the
  // wheel-aided S; at rest along a corridor LO wanders by centimetres from scan to scan).
  std::function<bool(Stamp, Stamp)> wheels_at_rest;
};

// How LIO initialized (or is still trying to).
struct InitializationRecord {
  bool admitted = false;
  InitMode mode = InitMode::kDeferred;  // of the admitted attempt (S or M), else the last decision
  std::string reason;                   // why that mode
  int initializations = 0;              // admitted so far, re-initializations after a divergence included
  Stamp first_imu = 0;                  // start of this initialization (its first IMU sample)
  Stamp admitted_at = 0;                // the newest node of the admitted window
  double latency_s = 0;                 // admitted_at - first_imu
  int scans = 0;                        // the admitted mode used
  double gravity_estimate = 0;          // m/s^2: S the mean specific force, M the free MAP estimate
  double tilt_sigma_deg = 0;            // M: predicted standard deviation of the gravity direction
  double lidar_sigma_m = 0;             // M: the LO position noise it found (at least lidar_position_sigma_m)
  double chi2_per_dof = 0;              // the admission check's
  SO3 R_world_imu;                      // the newest node's attitude in the gravity-aligned world
  Eigen::Vector3d gravity_imu = Eigen::Vector3d::Zero();  // gravity seen in that node's imu frame, m/s^2
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();     // that node's velocity, world, m/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero(), gyro_bias = Eigen::Vector3d::Zero();
  int attempts = 0, deferred = 0, rejected = 0;  // of this initialization
  std::vector<std::string> rejections;           // the first kMaxKeptRejections, "<stamp>: <mode>: <reason>"

  static constexpr int kMaxKeptRejections = 3;
  // One line for the report: "S (static) after 0.2 s, ...", or "" before the first admission.
  std::string Summary() const;
};

class InertialInitializer {
 public:
  // imu: the noise (preintegration) and gravity; imu_max_gap_s: the IMU gap the preintegrations refuse.
  InertialInitializer(const InertialInitConfig& config, const ImuNoiseParams& imu, double imu_max_gap_s);

  // Starts an initialization whose latency counts from `first_imu`: the window and the counts start again
  // (the record's initializations count goes on).
  void Start(Stamp first_imu);
  bool started() const { return started_; }

  struct Outcome {
    AdmissionCheck::Verdict verdict = AdmissionCheck::Verdict::kDeferred;
    // When admitted: the velocities of the newest nodes of the odometry window, from the first that the
    // initialization window covers (the older ones, before a rejected stretch, get none).
    InertialAlignment alignment;
    std::optional<std::string> warning;  // the first deferral and the first rejection
  };
  // One attempt with the odometry window `window` and its IMU samples `imu` (those not copied yet are); Start
  // must have been called.
  Outcome Attempt(const ImuBuffer& imu, const InitWindow& window);

  const InitializationRecord& record() const { return record_; }

 private:
  void Update(const ImuBuffer& imu, const InitWindow& window);
  std::vector<Eigen::Vector3d> NodeVelocities(const InertialAlignment& a, std::span<const Stamp> middles,
                                              std::span<const SE3> poses, const InitWindow& window) const;

  InertialInitConfig config_;
  ImuNoiseParams imu_params_;
  double imu_max_gap_s_;
  bool started_ = false;
  InitializationRecord record_;
  std::deque<InitScan> scans_;  // the initialization window, oldest first
  ImuBuffer imu_;               // the IMU samples from its first scan's begin on
  long last_window_id_ = -1;    // the newest scan id of the previous attempt's odometry window
  long first_allowed_id_ = 0;   // scans before it were dropped after a rejection
  long settled_id_ = 0;         // M uses the scans from this one on: the map's first map_settle_scans are not
  int map_scans_ = 0;           // scans of the current local map seen
  // M's gravity direction in "lo" at the previous attempt, when it was M with an estimate
  // (CheckGravitySettled).
  std::optional<Eigen::Vector3d> previous_gravity_;
};

}  // namespace uf::estimator
