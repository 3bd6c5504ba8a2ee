#include "odometry/eval/evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace uf {
namespace {

Expected<Association> Associate(const Trajectory& reference, const Trajectory& estimate,
                                const EvalOptions& options) {
  if (reference.has_stamps() != estimate.has_stamps())
    return Status::Error(std::string("the ") + (reference.has_stamps() ? "estimate" : "reference") +
                         " has no stamps but the other has: give its times file (--ref-times/--est-times)");
  if (!reference.has_stamps()) return AssociateByIndex(reference.size(), estimate.size());
  return AssociateByStamp(reference.stamps, estimate.stamps, options.max_dt, options.estimate_offset);
}

}  // namespace

Expected<EvalResult> Evaluate(const Trajectory& reference, const Trajectory& estimate,
                              const EvalOptions& options) {
  EvalResult result;
  // 1. Associate the poses.
  auto association = Associate(reference, estimate, options);
  if (!association) return association.status();
  result.association = std::move(*association);
  result.stamped = estimate.has_stamps();
  const std::size_t matched = result.association.size();
  if (matched < 2 && !result.stamped)
    return Status::Error("too few poses: " + std::to_string(matched) + " (need at least 2)");
  if (matched < 2) {
    char max_dt[32];
    std::snprintf(max_dt, sizeof(max_dt), "%g", ToSeconds(options.max_dt));
    return Status::Error("too few matched pairs: " + std::to_string(matched) + " of " +
                         std::to_string(estimate.size()) + " estimate poses lie within " + max_dt +
                         " s of a reference stamp (check the time base, --max-dt or --t-offset)");
  }
  for (std::size_t k = 0; k < matched; ++k) {
    const std::size_t i = result.association.reference[k], j = result.association.estimate[k];
    result.reference.push_back(reference.poses[i]);
    result.estimate.push_back(estimate.poses[j]);
    result.seconds.push_back(
        estimate.has_stamps()
            ? ToSeconds(estimate.stamps[j] - estimate.stamps[result.association.estimate[0]])
            : static_cast<double>(k));
  }

  // 2. Align the estimate onto the reference (Umeyama on the matched positions; yaw only: the 2D Procrustes
  // angle about z, WeightedRigidAlignment).
  if (options.align == AlignMode::kYaw) {
    const std::vector<Eigen::Vector3d> source = Positions(result.estimate),
                                       target = Positions(result.reference);
    double spread = 0;
    for (const Eigen::Vector3d& p : source) spread = std::max(spread, (p - source.front()).head<2>().norm());
    if (spread < 1e-9) return Status::Error("yaw alignment: the estimate does not move horizontally");
    const std::vector<double> weights(source.size(), 1.0);
    const SE3 T = WeightedRigidAlignment(source, target, weights, /*yaw_only=*/true);
    result.alignment = Similarity{T.so3(), T.translation(), 1.0};
    for (SE3& pose : result.estimate) pose = result.alignment * pose;
  } else if (options.align != AlignMode::kNone) {
    auto alignment =
        Umeyama(Positions(result.estimate), Positions(result.reference), options.align == AlignMode::kSim3);
    if (!alignment) return alignment.status();
    result.alignment = *alignment;
    for (SE3& pose : result.estimate) pose = result.alignment * pose;
  }

  // 3. Absolute translation error per matched pair.
  for (std::size_t k = 0; k < matched; ++k)
    result.ape_errors.push_back(
        (result.reference[k].translation() - result.estimate[k].translation()).norm());
  result.ape = ComputeStats(result.ape_errors);

  // 4. Relative translation error over pairs chosen on the (aligned) estimate.
  result.rpe_pairs = options.rpe_unit == RpeUnit::kFrames
                         ? PairsByFrames(matched, static_cast<std::size_t>(std::llround(options.rpe_delta)))
                         : PairsByPath(result.estimate, options.rpe_delta);
  result.rpe_errors = RelativeTranslationErrors(result.reference, result.estimate, result.rpe_pairs);
  if (!result.rpe_errors.empty()) result.rpe = ComputeStats(result.rpe_errors);

  // 5. KITTI drift over segments of the reference path.
  if (options.kitti_drift) result.kitti_drift = ComputeKittiDrift(result.reference, result.estimate);
  return result;
}

}  // namespace uf
