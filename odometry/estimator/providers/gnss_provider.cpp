#include "odometry/estimator/providers/gnss_provider.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "odometry/estimator/gnss/fix_screening.h"
#include "odometry/estimator/gnss/integrity_check.h"
#include "odometry/estimator/schedule/gnss_score.h"
#include "odometry/estimator/state/nav_state.h"

namespace uf::estimator {
namespace {

// Every GNSS factor carries this tag: they leave the window only through the marginalization of their
// nodes, never by tag.
constexpr long kGnssTag = 0;

std::vector<Stamp> Stamps(std::span<const NodeView> nodes) {
  std::vector<Stamp> stamps;
  stamps.reserve(nodes.size());
  for (const NodeView& node : nodes) stamps.push_back(node.stamp);
  return stamps;
}

// The antenna in the world at a placement: T(alpha) l with T slerped between the two nodes' poses.
Eigen::Vector3d AntennaWorld(std::span<const NodeView> nodes, const FixPlacement& at,
                             const Eigen::Vector3d& lever_arm) {
  const SE3 T =
      Interpolate(PoseFromBlock(nodes[at.node_a].pose), PoseFromBlock(nodes[at.node_b].pose), at.alpha);
  return T * lever_arm;
}

std::string Meters(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value << " m";
  return text.str();
}

}  // namespace

GnssProvider::GnssProvider(const GnssFactorConfig& config, const Eigen::Vector3d& lever_arm)
    : config_(config),
      lever_arm_(lever_arm),
      step_guard_(GnssStepRule{.gate = config.integrity_gate, .max_hold_s = config.step_max_hold_s}) {}

std::optional<std::string> GnssProvider::Add(const GnssFix& fix) {
  const std::string name = "GNSS fix at " + StampText(fix.stamp);
  if (std::optional<std::string> why = ScreenFix(fix, config_)) {
    ++counts_.skipped;
    return name + " skipped: " + *why;
  }
  if (has_last_ && fix.stamp <= last_stamp_) {
    ++counts_.skipped;
    return name + " skipped: not after " + StampText(last_stamp_);
  }
  Expected<Eigen::Vector3d> enu = origin_.ToEnu(fix);
  if (!enu) {
    ++counts_.skipped;
    return name + " skipped: " + enu.error();
  }
  has_last_ = true;
  last_stamp_ = fix.stamp;
  queue_.push_back({fix.stamp, *enu, FixCovariance(fix, config_), fix.status});
  return std::nullopt;
}

void GnssProvider::Link(FactorGraph& graph, std::span<const NodeView> nodes,
                        std::vector<std::string>& warnings) {
  if (nodes.empty()) return;
  const std::vector<Stamp> stamps = Stamps(nodes);
  if (aligned_ && !offsets_.empty()) ExtendOffsets(graph, nodes);
  const Stamp covered = stamps.back() + FromSeconds(config_.max_snap_s);
  bool new_pairs = false;
  while (!queue_.empty() && queue_.front().stamp <= covered) {
    const QueuedFix fix = queue_.front();
    queue_.pop_front();
    const std::optional<FixPlacement> at = PlaceFix(fix.stamp, stamps, config_);
    if (!at) {
      ++counts_.skipped;
      warnings.push_back("GNSS fixes skipped: no window node within " + std::to_string(config_.max_snap_s) +
                         " s or an interpolation gap (first at " + StampText(fix.stamp) + ")");
      continue;
    }
    if (aligned_) {
      AddFactor(graph, nodes, stamps, *at, fix, warnings);
    } else {
      pairs_.push_back({AntennaWorld(nodes, *at, lever_arm_), fix.enu, HorizontalWeight(fix.covariance)});
      paired_.push_back(fix);
      new_pairs = true;
    }
  }
  if (new_pairs) TryStartAlignment(graph, nodes, stamps, warnings);
}

// The closed-form start (gnss/alignment_init.h). A start refused for its residual RMS (a jump among the
// pairs, or odometry that drifted while the antenna covered the baseline) begins the collection again; a
// start refused for a short baseline or too few fixes waits for more.
void GnssProvider::TryStartAlignment(FactorGraph& graph, std::span<const NodeView> nodes,
                                     const std::vector<Stamp>& stamps, std::vector<std::string>& warnings) {
  Expected<AlignmentInit> start = InitializeAlignment(pairs_, config_);
  if (!start) {
    alignment_summary_ = "not started: " + start.error();
    const bool enough = static_cast<int>(pairs_.size()) >= config_.min_alignment_fixes &&
                        HorizontalBaseline(pairs_) >= config_.min_alignment_baseline_m;
    if (enough) {
      warnings.push_back(start.error() + "; collecting the pairs again");
      pairs_.clear();
      paired_.clear();
    }
    return;
  }
  aligned_ = true;
  alignment_ = AlignmentBlock(start->alignment);
  graph.AddEuclideanBlock(alignment_.data(), kGnssAlignmentSize);
  std::ostringstream summary;
  summary << "started at " << StampText(paired_.back().stamp) << " from " << start->pairs << " fixes over "
          << Meters(start->baseline_m) << ", RMS " << Meters(start->rms_m) << ", yaw "
          << start->alignment.yaw_rad * 180.0 / M_PI << " deg";
  alignment_summary_ = summary.str();
  // The pairs whose nodes are still in the window become factors (the integrity test uses the start).
  last_accepted_antenna_ = pairs_.back().antenna_world;
  for (const QueuedFix& fix : paired_)
    if (fix.stamp >= nodes.front().stamp)
      if (const std::optional<FixPlacement> at = PlaceFix(fix.stamp, stamps, config_))
        AddFactor(graph, nodes, stamps, *at, fix, warnings);
  pairs_.clear();
  paired_.clear();
}

void GnssProvider::ExtendOffsets(FactorGraph& graph, std::span<const NodeView> nodes) {
  for (const NodeView& node : nodes) {
    if (!offsets_.empty() && node.stamp <= offsets_.back().stamp) continue;
    OffsetState& offset = offsets_.emplace_back(OffsetState{node.stamp, {}});
    graph.AddEuclideanBlock(offset.value.data(), kGnssOffsetSize);
    if (offsets_.size() == 1) {
      graph.Add(FactorKind::kGnss, kGnssTag, MakeGnssOffsetPrior(offset_sigma_), nullptr,
                {offset.value.data()}, /*anchors=*/true);
      continue;
    }
    OffsetState& previous = offsets_[offsets_.size() - 2];
    const double dt = ToSeconds(offset.stamp - previous.stamp);
    const double tau = config_.offset_correlation_time_s;
    // Starts at the process's prediction a b_{k-1}.
    Eigen::Map<Eigen::Vector3d>(offset.value.data()) =
        std::exp(-dt / tau) * Eigen::Map<const Eigen::Vector3d>(previous.value.data());
    graph.Add(FactorKind::kGnss, kGnssTag, MakeGnssOffsetProcessFactor(dt, tau, offset_sigma_), nullptr,
              {previous.value.data(), offset.value.data()});
  }
}

double* GnssProvider::OffsetFor(std::span<const NodeView> nodes, const FixPlacement& at,
                                GnssFixStatus status) {
  if (offsets_.empty() || config_.Noise(status).offset_share <= 0) return nullptr;
  const Stamp node = nodes[at.single_node() || at.alpha < 0.5 ? at.node_a : at.node_b].stamp;
  const auto it = std::lower_bound(offsets_.begin(), offsets_.end(), node,
                                   [](const OffsetState& o, Stamp stamp) { return o.stamp < stamp; });
  return it != offsets_.end() && it->stamp == node ? it->value.data() : nullptr;
}

std::vector<double*> GnssProvider::StateBlocks() {
  std::vector<double*> blocks;
  if (!aligned_) return blocks;
  blocks.push_back(alignment_.data());
  for (OffsetState& offset : offsets_) blocks.push_back(offset.value.data());
  return blocks;
}

std::vector<double*> GnssProvider::OffsetBlocksUpTo(Stamp stamp) {
  std::vector<double*> blocks;
  for (OffsetState& offset : offsets_)
    if (offset.stamp <= stamp) blocks.push_back(offset.value.data());
  return blocks;
}

void GnssProvider::DropOffsetsUpTo(Stamp stamp) {
  while (!offsets_.empty() && offsets_.front().stamp <= stamp) offsets_.pop_front();
}

void GnssProvider::AddFactor(FactorGraph& graph, std::span<const NodeView> nodes,
                             const std::vector<Stamp>& stamps, const FixPlacement& at, const QueuedFix& fix,
                             std::vector<std::string>& warnings) {
  const double share = config_.Noise(fix.status).offset_share;
  if (share > 0) {
    offset_sigma_ = (share * fix.covariance.diagonal()).cwiseSqrt();
    if (offsets_.empty()) ExtendOffsets(graph, nodes);
  }
  // The fix less its offset's estimate (zero without one): what the window's prediction should meet.
  auto corrected = [&](const FixPlacement& place, const QueuedFix& f) -> Eigen::Vector3d {
    const double* offset = OffsetFor(nodes, place, f.status);
    return offset ? Eigen::Vector3d(f.enu - Eigen::Map<const Eigen::Vector3d>(offset)) : f.enu;
  };
  const EnuAlignment alignment = AlignmentFromBlock(alignment_.data());
  const Eigen::Vector3d antenna = AntennaWorld(nodes, at, lever_arm_);
  const double distance_m = last_accepted_antenna_ ? (antenna - *last_accepted_antenna_).norm() : 0.0;
  const IntegrityResult check =
      CheckIntegrity(antenna, alignment, corrected(at, fix), fix.covariance, distance_m, config_);
  if (std::isfinite(check.d2)) {  // a non-finite prediction is rejected below, and not in the statistics
    horizontal_innovations_.push_back(check.innovation.head<2>().norm());
    d2_sum_ += check.d2;
  }
  // The step guard sees every fix with a prediction, whatever the innovation test says of it, and the
  // previous one's innovation under the current estimate.
  std::optional<Eigen::Vector3d> previous_now;
  if (last_tested_)
    if (const std::optional<FixPlacement> was = PlaceFix(last_tested_->stamp, stamps, config_))
      previous_now = CheckIntegrity(AntennaWorld(nodes, *was, lever_arm_), alignment,
                                    corrected(*was, *last_tested_), last_tested_->covariance, 0.0, config_)
                         .innovation;
  const bool was_holding = step_guard_.holding();
  const bool guard_admits =
      !std::isfinite(check.d2) ||
      step_guard_.Admit(fix.stamp, check.innovation, fix.covariance, antenna, previous_now);
  if (std::isfinite(check.d2)) last_tested_ = fix;
  checks_.push_back(ScoreGnssFix(fix.stamp, fix.status, fix.covariance.trace(), check.d2,
                                 config_.integrity_gate, check.horizontal_accepted && guard_admits));
  if (!guard_admits) {
    ++counts_.rejected;
    ++held_out_;
    if (!was_holding) {
      std::ostringstream why;
      why << "GNSS fix at " << StampText(fix.stamp) << " held out by the step guard: its innovation "
          << "stepped from the previous fix's (d^2 " << step_guard_.last_step_d2()
          << "; multipath?); the next fixes too until one is back";
      warnings.push_back(why.str());
    }
    return;
  }
  if (!check.horizontal_accepted) {
    ++counts_.rejected;
    std::ostringstream why;
    why << "GNSS fix at " << StampText(fix.stamp) << " rejected by the integrity check: innovation "
        << Meters(check.innovation.norm()) << ", horizontal d^2 " << check.d2_horizontal << ", d^2 "
        << check.d2 << " (gate " << config_.integrity_gate << " for 3 dof)";
    warnings.push_back(why.str());
    return;
  }
  const GnssAxes axes = check.accepted ? GnssAxes::kAll : GnssAxes::kHorizontal;
  if (!check.accepted) {
    ++horizontal_only_;
    std::ostringstream why;
    why << "GNSS fix at " << StampText(fix.stamp) << " used horizontally: its height failed the integrity "
        << "check (vertical innovation " << Meters(std::abs(check.innovation.z())) << ", d^2 "
        << check.d2_vertical << ")";
    warnings.push_back(why.str());
  }
  // With an offset the fix keeps only the white share of its covariance.
  double* offset = OffsetFor(nodes, at, fix.status);
  const Eigen::Matrix3d white = offset ? Eigen::Matrix3d((1.0 - share) * fix.covariance) : fix.covariance;
  std::unique_ptr<ceres::CostFunction> cost;
  std::vector<double*> blocks;
  if (at.single_node()) {
    cost = std::make_unique<GnssFactorSinglePose>(fix.enu, white, lever_arm_, axes);
    blocks = {nodes[at.node_a].pose, alignment_.data()};
  } else {
    cost = std::make_unique<GnssFactor>(fix.enu, white, lever_arm_, at.alpha, axes);
    blocks = {nodes[at.node_a].pose, nodes[at.node_b].pose, alignment_.data()};
  }
  if (offset) {
    cost = std::make_unique<GnssOffsetFactor>(std::move(cost), white, axes);
    blocks.push_back(offset);
  }
  graph.Add(FactorKind::kGnss, kGnssTag, std::move(cost), nullptr, std::move(blocks), /*anchors=*/true);
  ++counts_.added;
  last_accepted_antenna_ = antenna;
}

std::vector<GnssCheck> GnssProvider::TakeChecks(Stamp until) {
  std::vector<GnssCheck> taken;
  std::erase_if(checks_, [&](const GnssCheck& c) {
    if (c.stamp > until) return false;
    taken.push_back(c);
    return true;
  });
  std::sort(taken.begin(), taken.end(),
            [](const GnssCheck& a, const GnssCheck& b) { return a.stamp < b.stamp; });
  return taken;
}

void GnssProvider::Reset() {
  if (aligned_) last_alignment_ = alignment_;
  aligned_ = false;
  alignment_ = {};
  offsets_.clear();
  last_accepted_antenna_.reset();
  step_guard_.Reset();
  last_tested_.reset();
  pairs_.clear();
  paired_.clear();
  if (last_alignment_) alignment_summary_ += "; restarted after a re-initialization of the window";
}

void GnssProvider::Report(SensorFactorStats& stats) const {
  stats.gnss = counts_;
  stats.gnss_alignment = alignment_summary_;
  stats.gnss_horizontal_only = horizontal_only_;
  stats.gnss_held_out = held_out_;
  SensorFactorStats::Innovations& innovations = stats.gnss_innovations;
  innovations.tested = static_cast<int>(horizontal_innovations_.size());
  if (horizontal_innovations_.empty()) return;
  std::vector<double> sorted = horizontal_innovations_;
  std::sort(sorted.begin(), sorted.end());
  innovations.horizontal_median_m = NearestRank(sorted, 0.5);
  innovations.horizontal_p95_m = NearestRank(sorted, 0.95);
  innovations.mean_d2 = d2_sum_ / static_cast<double>(sorted.size());
}

std::optional<Georeference> GnssProvider::georeference() const {
  if (!origin_.frame() || (!aligned_ && !last_alignment_)) return std::nullopt;
  const double* block = aligned_ ? alignment_.data() : last_alignment_->data();
  return Georeference{origin_.frame()->origin(), AlignmentFromBlock(block).T_enu_world()};
}

}  // namespace uf::estimator
