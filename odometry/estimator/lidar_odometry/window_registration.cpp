// Registration of the newest scan (see odometry_window.h and docs/METHOD.md "Registration, acceptance and
// recovery"): ICP rounds from the first guess, fallback guesses when it fails, the acceptance test, and the
// restart of the local map after repeated rejections.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "odometry/estimator/lidar_odometry/odometry_window.h"
#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

constexpr double kConvergedTranslation = 0.005;  // m, registration converged when a round moves less
constexpr double kConvergedRotation = 0.001;     // rad
constexpr int kMinResiduals = 6;                 // a rigid pose has 6 dof
constexpr std::size_t kMatchHistory = 10;        // registered scans behind the reference match fraction
constexpr double kMovedTranslation = 0.1;        // m: a scan this far from the last registered one moved
constexpr double kMovedRotation = 0.035;         // rad (2 deg): or turned this much
constexpr double kFarGuessRatio = 0.1;  // a first guess with fewer points on planes is far off (FarGuess)
constexpr double kSearchTurn = 15 * std::numbers::pi / 180;  // rad: beyond the ICP rounds' reliable basin
constexpr std::size_t kTurnHistory = 5;                      // registered scans behind GuessesTurnFar

}  // namespace

// The ICP rounds of the new scan from the poses its nodes hold now: re-query the planes after each solve
// until the scan's begin and end poses move less than kConvergedTranslation / kConvergedRotation in a
// round, or come back to where an earlier round left them (the association then cycles through the same few
// plane sets: further rounds only repeat the cycle), or association_rounds is reached. Only the new scan's
// nodes move. Returns false when a solve fails. rounds: against the coarse map, with the sweep rigid
// (Rounds).
bool LidarOdometry::Impl::RegisterRounds(ScanState& current, Rounds rounds) {
  std::vector<std::pair<SE3, SE3>> visited;  // (begin, end) poses after each round
  auto near = [](const SE3& a, const SE3& b) {
    const SE3 step = a.inverse() * b;
    return step.translation().norm() < kConvergedTranslation && step.so3().angle() < kConvergedRotation;
  };
  visited.emplace_back(NodePose(current.begin_node), NodePose(current.end_node));
  for (int round = 0; round < config.association_rounds; ++round) {
    const SE3 begin_in_end = NodePose(current.end_node).inverse() * NodePose(current.begin_node);
    Associate(current, rounds);
    if (!Solve(&stats.iterations, /*new_scan_only=*/true, rounds.rigid)) return false;
    if (rounds.rigid) NodeAt(current.begin_node).pose = PoseBlock(NodePose(current.end_node) * begin_in_end);
    const SE3 begin = NodePose(current.begin_node), end = NodePose(current.end_node);
    const bool repeated = std::any_of(visited.begin(), visited.end(), [&](const std::pair<SE3, SE3>& seen) {
      return near(seen.first, begin) && near(seen.second, end);
    });
    if (repeated) break;
    visited.emplace_back(begin, end);
  }
  return true;
}

// ICP rounds from a guess that may be far off: against the coarse map first (planes from blocks kCoarseScale
// times wider, a gate as much wider), which reaches surfaces that far from where the guess puts the points,
// then against the map. A sweep with nodes of its own is held rigid in the coarse rounds (HoldsSweepRigid).
// The coarse rounds take the fine rounds' robust kernel (lo.huber_m); with both_kernels (the first guess)
// the scan is registered twice from the guess, the second time with a kernel kCoarseScale times wider in the
// coarse rounds, scaled like their gate (Rounds::wide_kernel), and the result with the higher match fraction
// is kept. Each kernel alone settles in wrong minima where the other lands right (simulated hand-held wild,
// the first scans of a walk: docs/METHOD.md "Far first guesses"). Returns false when every attempt's solve
// failed.
bool LidarOdometry::Impl::RegisterCoarseToFine(ScanState& current, bool both_kernels) {
  const SavedStates guess = Save(nodes);
  std::optional<SavedStates> best;
  double best_fraction = -1;
  bool last_is_best = false;
  for (const bool wide_kernel : {false, true}) {
    if (wide_kernel && !both_kernels) break;
    Restore(guess, nodes);
    last_is_best = false;
    if (!RegisterRounds(current,
                        {.coarse = true, .rigid = HoldsSweepRigid(current), .wide_kernel = wide_kernel}) ||
        !RegisterRounds(current) || current.MatchFraction() <= best_fraction)
      continue;
    best = Save(nodes);
    best_fraction = current.MatchFraction();
    last_is_best = true;
  }
  if (!best) return false;
  if (!last_is_best) {
    Restore(*best, nodes);
    Associate(current);  // the factors of the kept result (the graph holds the last attempt's)
  }
  return true;
}

// The match fraction the recent registered scans that moved reached (their median), the yardstick of the
// acceptance test; 0 before any.
double LidarOdometry::Impl::ReferenceMatchFraction() const {
  if (recent_match_fractions.empty()) return 0;
  std::vector<double> sorted(recent_match_fractions.begin(), recent_match_fractions.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return sorted[sorted.size() / 2];
}

// Why the new scan's registration is not to be trusted, or nullopt (docs/METHOD.md "Registration,
// acceptance and recovery"): a failed solve or non-finite state, fewer than 6 planes, a match fraction
// below min_match_ratio of what the recent scans reached (a wrong alignment leaves most points off the
// planes, whatever the size of the correction), or a motion faster than max_speed_mps /
// max_angular_rate_rad_s allow: since the last registered scan, or within the scan's own sweep (begin to
// end node; a registration that slid into a wrong minimum can bend the sweep instead, 8-23 m within one
// 0.1 s sweep on simulated hand-held wild at 2 Hz).
std::optional<std::string> LidarOdometry::Impl::RejectionReason(const ScanState& current, bool solved) {
  if (!solved) return "solver failure";
  if (!AllFinite(nodes)) return "non-finite state";
  if (current.residuals < kMinResiduals)
    return std::to_string(current.residuals) + " of its points near a map plane, need " +
           std::to_string(kMinResiduals);
  const double reference = ReferenceMatchFraction();
  if (current.MatchFraction() < config.min_match_ratio * reference)
    return PrintfText("%.0f %% of its points on a map plane, the recent scans %.0f %%",
                      100 * current.MatchFraction(), 100 * reference);
  const auto too_fast = [&](const SE3& from, const SE3& to, Stamp duration) {
    const double dt = std::max(ToSeconds(duration), 1e-3);
    const SE3 motion = from.inverse() * to;
    const double distance = motion.translation().norm(), angle = motion.so3().angle();
    return distance > config.max_speed_mps * dt || angle > config.max_angular_rate_rad_s * dt
               ? std::optional(PrintfText("moved %.2f m and %.0f deg in %.2f s", distance,
                                          angle * 180 / std::numbers::pi, dt))
               : std::nullopt;
  };
  const SE3 end = NodePose(current.end_node);
  if (current.begin_node != current.end_node)
    if (auto fast = too_fast(NodePose(current.begin_node), end,
                             NodeAt(current.end_node).stamp - NodeAt(current.begin_node).stamp))
      return *fast + " within its sweep";
  if (last_registered)
    if (auto fast = too_fast(last_registered->pose, end, current.end - last_registered->stamp))
      return *fast + " since the last registered scan";
  return std::nullopt;
}

// In initialized LIO: whether the registration from the IMU prediction stayed within kAgreeTranslation /
// kAgreeRotation of it and matched at least min_match_ratio / 2 of the yardstick. The IMU is an independent
// witness over the short interval since the last scan: a registration it agrees with is not a wrong minimum,
// its low match fraction comes from the scene (a stretch with few planes, a part of the map not seen before),
// and rejecting it would leave the window to the IMU alone (simulated urban, 1 hour: three scans in such a
// stretch were rejected and the local map restarted).
bool LidarOdometry::Impl::AgreesWithGuess(const ScanState& current, const SavedStates& guess) {
  constexpr double kAgreeTranslation = 0.1, kAgreeRotation = 0.0175;  // m, rad (1 deg)
  if (!AllFinite(nodes) || current.residuals < kMinResiduals ||
      current.MatchFraction() < 0.5 * config.min_match_ratio * ReferenceMatchFraction())
    return false;
  const SE3 moved = MoveFromGuess(current, guess);
  return moved.translation().norm() <= kAgreeTranslation && moved.so3().angle() <= kAgreeRotation;
}

// The guesses tried (each with coarse rounds first) when the first one (the IMU prediction in LIO, the
// constant-velocity extrapolation over the last node pair in LO) fails or matches poorly, from the nodes as
// they were before its rounds: the first guess itself with both kernels (RegisterCoarseToFine; unless
// first_done: a far first guess was registered so already), and when the first result was poor (rejected, or
// below kPoorRatio of the recent match fraction) also constant velocity over the last scan interval (at least
// kLongTwistBaseline: steadier than one sweep's twist, which rests on the deskew alone) and no motion since
// the last registered scan.
std::vector<LidarOdometry::Impl::Guess> LidarOdometry::Impl::FallbackGuesses(const ScanState& current,
                                                                             bool poor, bool first_done) {
  constexpr Stamp kLongTwistBaseline = 150'000'000;  // 0.15 s
  std::vector<Guess> guesses;
  if (!first_done)
    guesses.push_back({"first guess (coarse to fine)", NodePose(current.begin_node),
                       NodePose(current.end_node),
                       /*both_kernels=*/true});
  if (!poor) return guesses;
  const long last_old = SharesBeginNode(current) ? current.begin_node : current.begin_node - 1;
  if (last_old > first_node_id)
    guesses.push_back({"steady-velocity guess", ExtrapolateFrom(last_old, current.stamp, kLongTwistBaseline),
                       ExtrapolateFrom(last_old, current.end, kLongTwistBaseline)});
  if (last_registered) guesses.push_back({"zero-motion guess", last_registered->pose, last_registered->pose});
  return guesses;
}

// The last resort when no guess was accepted: the zero-motion guess turned about the body's z axis by
// +-kTurnStep and +-2 kTurnStep. A device carried by hand looks around mostly about its vertical axis, and at
// 2 Hz keyframes it turns by up to ~35 deg between scans (simulated handheld), beyond what even the coarse
// rounds reach from a guess that far off.
std::vector<LidarOdometry::Impl::Guess> LidarOdometry::Impl::TurnedGuesses() {
  constexpr double kTurnStep = 20 * std::numbers::pi / 180;
  std::vector<Guess> guesses;
  if (!last_registered) return guesses;
  for (const double turn : {kTurnStep, -kTurnStep, 2 * kTurnStep, -2 * kTurnStep}) {
    const SE3 turned =
        last_registered->pose * SE3(SO3::Exp(Eigen::Vector3d(0, 0, turn)), Eigen::Vector3d::Zero());
    guesses.push_back(
        {PrintfText("zero-motion guess turned by %+.0f deg", turn * 180 / std::numbers::pi), turned, turned});
  }
  return guesses;
}

// How the registration moved the scan's end node from where the guess put it (in the guess's frame).
SE3 LidarOdometry::Impl::MoveFromGuess(const ScanState& current, const SavedStates& guess) const {
  const std::size_t end = static_cast<std::size_t>(current.end_node - first_node_id);
  return PoseFromBlock(guess.poses[end].data()).inverse() * NodePose(current.end_node);
}

// Whether the first guesses of the recent scans kept apart lay beyond the rounds' reliable basin: one of the
// last kTurnHistory registered ones turned more than kSearchTurn from its guess (MoveFromGuess). From that
// far, the rounds also settle in wrong minima that match as many points as the right one, near the guess or
// after a large turn (simulated hand-held wild at 2 Hz: guesses 15-38 deg off, median 24 deg; wrong minima
// accepted at 82-115 % of the recent match fraction; one right after the first large turn of the walk, its
// guess already in the wrong basin). The KITTI keyframes' guesses are within 11 deg.
bool LidarOdometry::Impl::GuessesTurnFar() const {
  return std::any_of(recent_guess_turns.begin(), recent_guess_turns.end(),
                     [](double turn) { return turn > kSearchTurn; });
}

// Whether the scan's begin node is the previous scan's end node (it started where that one ended).
bool LidarOdometry::Impl::SharesBeginNode(const ScanState& current) const {
  return window.size() >= 2 && window[window.size() - 2].end_node == current.begin_node;
}

// Whether the first guess is far off: before any solve, the share of the scan's points on map planes is below
// kFarGuessRatio of the recent scans' (ReferenceMatchFraction), or there is no such yardstick yet. Measured
// at the guess: KITTI keyframes 0.07-1.0 of the yardstick (median 0.47), simulated hand-held keyframes at 2
// Hz 0.01-0.17 (median 0.02). Associates the scan at its guess (the fine rounds' first association then finds
// its planes cached).
bool LidarOdometry::Impl::FarGuess(ScanState& current) {
  Associate(current);
  const double reference = ReferenceMatchFraction();
  return reference == 0 || current.MatchFraction() < kFarGuessRatio * reference;
}

// Whether the registered scan is the first to move (kMovedTranslation) after one that had not: its first
// guess, the constant-velocity extrapolation, came from the rest and may be a whole step behind, where the
// fine rounds settle in a wrong minimum that matches as many points as the recent scans (simulated hand-held
// wild at 2 Hz, the first scan of the walk: 0.25 m behind, registered 0.36 m off at 1.03 of the recent match
// fraction, where the first guess coarse to fine matches 1.56 times as many points on planes and lands
// right). Also the second scan of a map, whose first has a single node and no motion.
bool LidarOdometry::Impl::MovesOffFromRest(const ScanState& current) const {
  if (!last_registered || last_move_m >= kMovedTranslation) return false;
  return (last_registered->pose.inverse() * NodePose(current.end_node)).translation().norm() >=
         kMovedTranslation;
}

// Whether the coarse rounds hold the scan's sweep rigid (Rounds::rigid): in LO, for a sweep with a begin and
// an end node of its own (scans kept apart, such as keyframes). Its two free nodes give the registration 12
// dof, and from a far guess the coarse rounds bend the sweep into a wrong minimum: simulated hand-held wild
// at 2 Hz, sweeps of 0.1 s stretched to 8-23 m. Rigid, the coarse rounds move it as a whole (as KISS-ICP
// registers a scan deskewed by its prediction); the fine rounds then free both nodes from there. With a
// shared begin node the sweep continues the last one and has 6 dof anyway; in LIO the IMU holds the sweep.
bool LidarOdometry::Impl::HoldsSweepRigid(const ScanState& current) const {
  return !inertial && current.begin_node != current.end_node && !SharesBeginNode(current);
}

// Registration of the newest scan (the window's last): ICP rounds from the first guess. When the acceptance
// test rejects them, or their match fraction is below kRetryRatio of the recent scans' (a registration that
// slid into a wrong minimum may still pass the test, with fewer points on planes than usual), or in LO the
// guesses of scans kept apart lie beyond the rounds' reliable basin (MoveFromGuess, GuessesTurnFar) or the
// scan is the first to move after a rest (MovesOffFromRest), the same from each fallback guess (and from the
// turned guesses where the guesses turn far), keeping the accepted result with the highest match fraction;
// then one solve of the whole window. When nothing is accepted the guess is
// restored, the scan's factors dropped, and the scan stays out of the map.
bool LidarOdometry::Impl::RegisterNewScan(ScanState& current) {
  constexpr double kRetryRatio = 0.85, kPoorRatio = 0.75, kClearlyMore = 1.05;
  const SavedStates saved = Save(nodes);
  const bool far = HoldsSweepRigid(current) && FarGuess(current);
  bool solved = far ? RegisterCoarseToFine(current, /*both_kernels=*/true) : RegisterRounds(current);
  std::optional<std::string> why = RejectionReason(current, solved);
  if (why && inertial && solved && AgreesWithGuess(current, saved)) why.reset();
  const double ratio = current.MatchFraction() / std::max(ReferenceMatchFraction(), 1e-9);
  const bool beyond_basin = HoldsSweepRigid(current) &&
                            (GuessesTurnFar() || MoveFromGuess(current, saved).so3().angle() > kSearchTurn);
  const bool off_from_rest = HoldsSweepRigid(current) && MovesOffFromRest(current);
  if (why || ratio < kRetryRatio || beyond_basin || off_from_rest) {
    std::optional<SavedStates> best;
    double best_fraction = -1;
    std::string best_guess;
    if (!why) {  // the first guess's result stays unless a fallback matches clearly more
      best = Save(nodes);
      best_fraction = kClearlyMore * current.MatchFraction();
    }
    const std::string first =
        why ? *why : PrintfText("%.0f %% of its points on a map plane", 100 * current.MatchFraction());
    const auto try_guesses = [&](const std::vector<Guess>& guesses) {
      for (const Guess& guess : guesses) {
        Restore(saved, nodes);
        if (!SharesBeginNode(current)) NodeAt(current.begin_node).pose = PoseBlock(guess.begin);
        NodeAt(current.end_node).pose = PoseBlock(guess.end);
        const bool ok = RegisterCoarseToFine(current, guess.both_kernels);  // a fallback guess may be far off
        if (RejectionReason(current, ok) || current.MatchFraction() <= best_fraction) continue;
        best = Save(nodes);
        best_fraction = current.MatchFraction();
        best_guess = guess.name;
      }
    };
    Restore(saved, nodes);  // the guesses start from the nodes as they were before the rounds
    const bool poor = why || ratio < kPoorRatio || beyond_basin;
    try_guesses(FallbackGuesses(current, poor, /*first_done=*/far));
    if ((!best && poor) || beyond_basin || off_from_rest) try_guesses(TurnedGuesses());
    if (best) {
      Restore(*best, nodes);
      Associate(current);  // the factors of the kept result (the graph holds the last attempt's)
      if (!best_guess.empty())
        events.push_back({TrackEvent::Kind::kFallbackGuess, current.stamp,
                          "registered from the " + best_guess + ", " +
                              PrintfText("%.0f %% of its points on a map plane", 100 * best_fraction) +
                              " (the first guess: " + first + ")"});
      why.reset();
    }
  }
  if (!why && (config.window_size > 2 || inertial)) {
    LinkGnss();  // the new nodes are registered: a fair prediction for the integrity test
    LinkVisual();
    Relinearize();
    solved = Solve(&stats.iterations);  // the whole window, once
    if (!solved || !AllFinite(nodes)) why = solved ? "non-finite window state" : "window solver failure";
    if (!why && visual) {
      visual->DropOutliers(graph);
      visual->RecordWindowTimeOffset();
    }
  }
  stats.residuals = current.residuals;
  current.plane_cache = {};  // the map changes next
  if (!why) {
    current.information = ScanInformation(current);
    if (wheel) current.forward_sigma_m = ForwardSigma(current);
    if (config.drop_weak_directions)
      DropWeakDirections(current);
    else if (wheel && config.wheel_carries_weak_translations)
      LeaveWeakTranslationsToWheel(current);
    // A scan taken where the last one was matches the map it just made almost fully: at a standstill the
    // match fraction says nothing of what a moving scan reaches, so only scans that moved count.
    const SE3 moved = last_registered ? last_registered->pose.inverse() * NodePose(current.end_node) : SE3();
    last_move_m = moved.translation().norm();
    if (last_move_m >= kMovedTranslation || moved.so3().angle() >= kMovedRotation) {
      recent_match_fractions.push_back(current.MatchFraction());
      if (recent_match_fractions.size() > kMatchHistory) recent_match_fractions.pop_front();
    }
    last_registered = RegisteredPose{current.end, NodePose(current.end_node)};
    if (HoldsSweepRigid(current)) {
      recent_guess_turns.push_back(MoveFromGuess(current, saved).so3().angle());
      if (recent_guess_turns.size() > kTurnHistory) recent_guess_turns.pop_front();
    }
    consecutive_rejections = 0;
    return true;
  }
  Restore(saved, nodes);
  graph.Remove(FactorKind::kLidar, current.id);
  current.residuals = 0;
  ++consecutive_rejections;
  warnings.push_back("lidar scan at " + StampText(current.stamp) + ": registration rejected (" + *why +
                     "); the scan keeps its predicted pose and stays out of the map");
  events.push_back({TrackEvent::Kind::kRejected, current.stamp, *why});
  return false;
}

}  // namespace uf::estimator
