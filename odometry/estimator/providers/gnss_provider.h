// The GNSS receiver's part of the window (docs/METHOD.md "GNSS factor"): it screens the fixes, places the
// ENU origin at the first good one, starts the world -> ENU alignment once the antenna has moved far enough,
// then links every later fix to the nodes around its stamp by a GnssFactor, after the innovation test
// against the window's prediction. Used by the windows whose world is gravity-aligned (LIO+G, LWGIO, WGIO);
// nothing in it depends on the LiDAR.
//
// A fix's life:
//   Add:  ScreenFix (status, finite, ranges, covariance) -> ENU at the origin -> queued
//   Link (after the window's nodes cover the fix's stamp, once per solve of the window):
//     PlaceFix among the nodes (none: dropped, counted as skipped)
//     not aligned yet: the pair (antenna at the interpolated pose, fix) joins the alignment start; once
//       InitializeAlignment accepts the pairs, the alignment block joins the graph and the pairs whose
//       nodes are still in the window become factors;
//     aligned: CheckIntegrity (rejected: counted, a warning with the innovation), else a GnssFactor
//       (anchors: it ties the window to the Earth, so marginalization keeps it in the prior).
// A fix whose status has an offset share (config/gnss_factor_config.h) also touches the receiver's offset
// at the node nearest to it (factors/gnss_offset_factor.h). The first such fix starts the offsets: one
// Euclidean block per node from then on, linked by the Gauss-Markov process; they leave with their nodes
// (OffsetBlocksUpTo, DropOffsetsUpTo) and the innovation test compares the fix less the offset's estimate.
// A re-initialization of the window (Reset: the graph cleared, the world continuing from the last pose)
// starts the alignment again from new pairs; until it is accepted, the last alignment stands for the
// georeference. The ENU origin stays, so the run keeps one georeference frame.
#pragma once

#include <Eigen/Core>
#include <array>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/factors/gnss_factor.h"
#include "odometry/estimator/factors/gnss_offset_factor.h"
#include "odometry/estimator/gnss/alignment_init.h"
#include "odometry/estimator/gnss/fix_placement.h"
#include "odometry/estimator/gnss/gnss_enu_origin.h"
#include "odometry/estimator/providers/sensor_factor_stats.h"
#include "odometry/estimator/schedule/gnss_step_guard.h"
#include "odometry/estimator/state/window_node.h"
#include "odometry/estimator/window/factor_graph.h"
#include "odometry/types/georeference.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"

namespace uf::estimator {

class GnssProvider {
 public:
  // lever_arm: the antenna in the window's body frame (m).
  GnssProvider(const GnssFactorConfig& config, const Eigen::Vector3d& lever_arm);
  GnssProvider(const GnssProvider&) = delete;  // the graph refers to alignment_
  GnssProvider& operator=(const GnssProvider&) = delete;

  // Screens the fix and queues it; returns why it was not used (a warning), nothing when queued. Fixes out
  // of time order are refused likewise.
  std::optional<std::string> Add(const GnssFix& fix);

  // Links the queued fixes up to the last node's stamp to `nodes` (the window's, increasing stamps; their
  // poses are the current estimate), appending a warning per rejected or unplaced fix and one when the
  // alignment starts.
  void Link(FactorGraph& graph, std::span<const NodeView> nodes, std::vector<std::string>& warnings);

  // The window restarted (its graph cleared): the alignment leaves the graph and starts again from new pairs
  // (a restart may follow a divergence, so the old value is not trusted for the innovation test).
  void Reset();

  bool aligned() const { return aligned_; }
  // The blocks a solve of the whole window moves: the alignment once aligned, and the offsets.
  std::vector<double*> StateBlocks();
  // The offsets of nodes with stamps up to `stamp`: to leave the window with their nodes, then to be
  // dropped once the graph no longer holds them.
  std::vector<double*> OffsetBlocksUpTo(Stamp stamp);
  void DropOffsetsUpTo(Stamp stamp);
  // Once aligned: the ENU origin (the first good fix) and the current world -> ENU transform (after a Reset,
  // the last one until the alignment starts again).
  std::optional<Georeference> georeference() const;
  // Its part of the window's report: factors added, fixes skipped (screened out, out of order, no node
  // near), rejected by the innovation test; how the alignment started.
  void Report(SensorFactorStats& stats) const;
  // The fixes the innovation test saw with stamps up to `until`, scored (ScoreGnssFix), in stamp order;
  // they are handed out once.
  std::vector<GnssCheck> TakeChecks(Stamp until);

 private:
  struct QueuedFix {
    Stamp stamp = 0;
    Eigen::Vector3d enu;
    Eigen::Matrix3d covariance;
    GnssFixStatus status = GnssFixStatus::kNoFix;
  };
  // stamps: the nodes' (Stamps(nodes)), for placing fixes among them.
  void TryStartAlignment(FactorGraph& graph, std::span<const NodeView> nodes,
                         const std::vector<Stamp>& stamps, std::vector<std::string>& warnings);
  void AddFactor(FactorGraph& graph, std::span<const NodeView> nodes, const std::vector<Stamp>& stamps,
                 const FixPlacement& at, const QueuedFix& fix, std::vector<std::string>& warnings);
  // One offset per node after the last one's (the first with the stationary prior).
  void ExtendOffsets(FactorGraph& graph, std::span<const NodeView> nodes);
  // The offset block of the node nearest the placement; null when the offsets have not started or the
  // fix's status has no offset share.
  double* OffsetFor(std::span<const NodeView> nodes, const FixPlacement& at, GnssFixStatus status);

  GnssFactorConfig config_;
  Eigen::Vector3d lever_arm_;
  GnssEnuOrigin origin_;
  std::deque<QueuedFix> queue_;  // screened, not linked yet
  Stamp last_stamp_ = 0;
  bool has_last_ = false;
  // The alignment start: the pairs so far and their fixes (to become factors once aligned).
  std::vector<AlignmentPair> pairs_;
  std::vector<QueuedFix> paired_;
  bool aligned_ = false;
  std::array<double, kGnssAlignmentSize> alignment_{};
  struct OffsetState {
    Stamp stamp = 0;  // its node's
    std::array<double, kGnssOffsetSize> value{};
  };
  std::deque<OffsetState> offsets_;  // grown at the back, dropped at the front: the blocks stay in place
  Eigen::Vector3d offset_sigma_ = Eigen::Vector3d::Ones();  // s of the last fix with an offset share
  std::optional<std::array<double, kGnssAlignmentSize>> last_alignment_;  // before the last Reset
  // The predicted antenna (world) at the last accepted fix or the alignment's start: the innovation test's
  // prediction uncertainty grows with the distance from it (gnss/integrity_check.h).
  std::optional<Eigen::Vector3d> last_accepted_antenna_;
  GnssStepGuard step_guard_;
  std::optional<QueuedFix> last_tested_;  // the last fix the step guard saw
  int held_out_ = 0;                      // of counts_.rejected: fixes the step guard held out
  FactorCount counts_;
  int horizontal_only_ = 0;  // of counts_.added: fixes whose height failed the innovation test
  std::vector<double> horizontal_innovations_;  // m, every fix tested
  double d2_sum_ = 0;
  std::vector<GnssCheck> checks_;  // scored, not taken yet
  std::string
      alignment_summary_;  // "started at ... from 8 fixes over 14.2 m, RMS 0.8 m, yaw ...", or why not
};

}  // namespace uf::estimator
