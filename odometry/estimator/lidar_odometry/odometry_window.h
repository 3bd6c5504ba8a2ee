// The sliding window behind LidarOdometry (private to this library): pose nodes at scan boundaries, the
// scans, the local map, and the factor graph (window/factor_graph.h) holding every factor between the nodes
// (point-to-plane residuals, the constant-velocity prior in LO, IMU preintegration in LIO) and the
// marginalization prior. The design is described in lidar_odometry.h; the methods live in lidar_odometry.cpp
// (scan flow, restart), window_nodes.cpp (nodes, IMU, initialization), window_init.cpp (feeding the
// initialization), window_extrinsic.cpp (a new LiDAR extrinsic), window_registration.cpp (registration,
// acceptance, fallback guesses), window_scans.cpp (association, map, coarse map, keyframes) and
// window_solve.cpp (solve, marginalize) and window_visual.cpp (the camera's landmarks, LVIO).
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/factors/constant_velocity_factor.h"
#include "odometry/estimator/factors/imu_factor.h"
#include "odometry/estimator/init/inertial_alignment.h"
#include "odometry/estimator/init/inertial_initializer.h"
#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/estimator/lidar_odometry/scan_preparation.h"
#include "odometry/estimator/lidar_odometry/sweep_poses.h"
#include "odometry/estimator/preintegration/imu_buffer.h"
#include "odometry/estimator/providers/gnss_provider.h"
#include "odometry/estimator/providers/visual_provider.h"
#include "odometry/estimator/providers/wheel_provider.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/estimator/state/window_node.h"
#include "odometry/estimator/window/factor_graph.h"

namespace uf::estimator {

constexpr int kCoarseScale = 4;  // the coarse map's voxels (and correspondence gate) relative to the map's

constexpr Stamp kSharedNodeTolerance = 1'000'000;  // 1 ms: a scan starting this close to the last node
                                                   // shares that node

// A state of the window (state/window_node.h). The factors that end at a node carry its id as their tag:
// the constant-velocity prior on (id - 2, id - 1, id) (LO, LIO before its initialization, LIO across an
// IMU gap) or the IMU factor on (id - 1, id).
using Node = WindowNode;

struct ScanState {
  long id = 0;  // the tag of its point-to-plane factors in the graph
  Stamp stamp = 0, end = 0;
  long begin_node = 0, end_node = 0;               // node ids (equal for a scan without duration)
  std::vector<PreparedPoint> points;               // all prepared points, for the keyframe's deskewed scan
  std::vector<PreparedPoint> map_points;           // downsampled at map_insert_voxel_m, for the map
  std::vector<PreparedPoint> registration_points;  // downsampled at input_voxel_m
  int residuals = 0;                               // point-to-plane factors of the last association
  int visited = 0;   // registration points its last association looked at to find them (a spread sample)
  int on_plane = 0;  // of those, the points within 2 sigmas of their map plane
  // The fraction of the points looked at that lie on a map plane: the registration's quality for the
  // acceptance test. A registration in a wrong minimum still has many points NEAR planes (within
  // max_plane_distance_m: floors, ceilings, long walls), but far fewer ON them.
  double MatchFraction() const { return visited > 0 ? static_cast<double>(on_plane) / visited : 0.0; }
  // The map's plane for each registration point, from its last query: within the ICP rounds of one scan
  // the map does not change, so a point still in the same voxel gets the same plane (VoxelHashMap::QueryKey)
  // and needs no new query. Valid for map revision plane_cache_revision; dropped after registration.
  struct CachedPlane {
    std::uint64_t key = VoxelHashMap::kNoQueryKey;
    bool known = false;
    std::optional<Plane> plane;
  };
  std::vector<CachedPlane> plane_cache;
  std::uint64_t plane_cache_revision = 0;
  bool plane_cache_coarse = false;  // the planes are the coarse map's
  bool in_map = false;              // registered (or the first scan of a map) and inserted into the map
  // With wheel factors: the standard deviation of the scan's position along the wheel's forward axis that
  // its own point-to-plane factors give (ForwardSigma); infinite when it has none. For the wheel scale's
  // observability test (WheelScaleObservable).
  double forward_sigma_m = std::numeric_limits<double>::infinity();
  // The information of its point-to-plane factors at registration (ScanInformation), none before or when
  // rejected: the wheel scale's test (ForwardSigma) and the keyframe's LiDAR degeneracy read it.
  std::optional<Matrix6d> information;
  // With config.drop_weak_directions (or wheel_carries_weak_translations), when the information leaves a
  // direction weak: the projector its point-to-plane factors are taken through (ProjectedFactor) from then
  // on.
  std::optional<Matrix6d> projector;
};

// How the ICP rounds of a new scan treat it (LidarOdometry::Impl::RegisterRounds). coarse: against the coarse
// map (CoarseMap) with a correspondence gate kCoarseScale times wider, for a far guess. rigid (a sweep with a
// begin and an end node of its own): the sweep moves as one body, its motion within the sweep as the guess
// has it (only its end node is solved for, the begin node follows; the motion factors stay out): 6 dof,
// where its two nodes give 12. wide_kernel: the robust kernel's scale lo.huber_m kCoarseScale times wider.
struct Rounds {
  bool coarse = false;
  bool rigid = false;
  bool wide_kernel = false;
};

// Adds the wall time of its scope to a millisecond counter (the per-stage figures of OdometryStats).
class StageTimer {
 public:
  explicit StageTimer(double& ms) : ms_(ms), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  double& ms_;
  std::chrono::steady_clock::time_point start_;
};

struct LidarOdometry::Impl {
  Impl(const LidarOdometryConfig& c, std::unique_ptr<VisualProvider> camera)
      : config(c), map(c.map), imu(c.imu, c.imu_max_gap_s), visual(std::move(camera)) {
    if (config.use_wheel) wheel = std::make_unique<WheelProvider>(config.wheel, config.T_body_wheel);
    if (config.use_gnss) gnss = std::make_unique<GnssProvider>(config.gnss, config.T_body_gnss.translation());
    given_lidar_translation = config.T_body_lidar.translation();
    std::copy(given_lidar_translation.data(), given_lidar_translation.data() + 3, lidar_translation.begin());
    if (visual)
      visual->SetMapDepth([this](const SE3& T_world_camera, const Eigen::Vector2d& xy) {
        return MapDepth(T_world_camera, xy);
      });
    AttachProviders();
  }

  LidarOdometryConfig config;
  VoxelHashMap map;
  std::unique_ptr<VoxelHashMap> coarse_map;  // CoarseMap(), for map revision coarse_map_revision
  std::uint64_t coarse_map_revision = 0;
  FactorGraph graph;
  std::deque<Node> nodes;  // ids first_node_id ...
  long first_node_id = 0;
  std::deque<ScanState> window;
  long next_scan_id = 0;
  std::vector<Keyframe> finished;
  // LIO before initialization: the keyframes that left the window in the LO frame, held until the alignment
  // rotates them into the gravity-aligned world with the window (at most kMaxHeldKeyframes; see Release).
  std::deque<Keyframe> held_for_alignment;
  static constexpr std::size_t kMaxHeldKeyframes = 200;
  bool released_unaligned = false;  // kMaxHeldKeyframes was exceeded (warned once)
  std::vector<std::string> warnings;
  OdometryStats stats;
  std::vector<OdometryStats> processed;  // since the last TakeProcessedStats
  SE3 restart_pose;  // the first node's guess (identity, or where a re-initialization starts)
  bool has_last = false;
  Stamp last_stamp = 0, last_end = 0;
  // Registration acceptance and recovery (window_registration.cpp).
  struct RegisteredPose {
    Stamp stamp = 0;  // the scan's end
    SE3 pose;         // its end node's pose when it was registered
  };
  std::optional<RegisteredPose> last_registered;  // the last scan accepted (or the first of a map)
  double last_move_m = 0;  // how far it moved from the one registered before it (0 for the first of a map)
  std::deque<double> recent_match_fractions;      // of the last registered scans
  std::deque<double> recent_guess_turns;  // rad: MoveFromGuess's angle, last registered scans kept apart
  int consecutive_rejections = 0;
  int scans_leaving_translations_to_wheel = 0;  // LeaveWeakTranslationsToWheel's, over the run
  std::vector<TrackEvent> events;  // since the last TakeEvents
  // LIO.
  ImuBuffer imu;                  // from before the oldest node on
  std::deque<LidarScan> pending;  // scans waiting for the IMU (and the wheel) to cover their end
  bool inertial = false;          // initialized: IMU factors active
  // The IMU's orientation when the initialization aligned the world with gravity, and the LiDAR extrinsic's
  // rotation then: where gravity lies in the world after a new extrinsic (window_extrinsic.cpp).
  struct GravityReference {
    SO3 R_world_imu, R_imu_lidar;
  };
  std::optional<GravityReference> gravity_reference;
  std::string init_summary;
  InertialInitializer initializer{config.init, config.imu, config.imu_max_gap_s};  // window_init.cpp
  // Optional factors.
  std::unique_ptr<WheelProvider> wheel;
  std::unique_ptr<GnssProvider> gnss;
  std::unique_ptr<VisualProvider> visual;    // LVIO
  std::vector<TrackedFrame> tracked_frames;  // the front end's, per frame since the last take
  // The LiDAR extrinsic's translation t_BL, a block of the graph (lio.estimate_lidar_translation;
  // window_extrinsic.cpp): config.T_body_lidar takes it after every window solve.
  std::array<double, 3> lidar_translation{};
  Eigen::Vector3d given_lidar_translation = Eigen::Vector3d::Zero();  // the prior's centre
  int lever_free_solves = 0, lever_solves = 0;
  // With it estimated: the keyframes that left before it settled, each with the translation its body pose
  // was computed with (window_extrinsic.cpp, Emit).
  struct LeverHeldKeyframe {
    Keyframe keyframe;
    Eigen::Vector3d lidar_translation;
  };
  std::deque<LeverHeldKeyframe> held_for_lever;
  std::deque<Eigen::Vector3d> recent_lever;              // after the last kLeverSettleSolves free solves
  static constexpr std::size_t kLeverSettleSolves = 20;  // free window solves over which it must settle
  static constexpr double kLeverSettledM = 0.005;        // how little it may move over them
  static constexpr std::size_t kMaxLeverHeld = 50;       // keyframes held at most (5 s at 10 Hz)

  // Nodes (window_nodes.cpp).
  Node& NodeAt(long id) { return nodes[static_cast<std::size_t>(id - first_node_id)]; }
  const Node& NodeAt(long id) const { return nodes[static_cast<std::size_t>(id - first_node_id)]; }
  long LastNodeId() const { return first_node_id + static_cast<long>(nodes.size()) - 1; }
  SE3 NodePose(long id) const { return PoseFromBlock(NodeAt(id).pose.data()); }
  NavState NodeState(long id) { return NodeNavState(NodeAt(id)); }
  SE3 Extrapolate(Stamp stamp) { return ExtrapolateFrom(LastNodeId(), stamp, 0); }
  SE3 ExtrapolateFrom(long id, Stamp stamp, Stamp baseline);
  long AddNode(Stamp stamp);
  void AddImuFactor(long id, std::unique_ptr<ImuFactor> factor);
  void AddMotionPrior(long id);
  void AddSweepVelocityPrior(const ScanState& scan);
  void LinkWheel(long id, WheelReference reference);
  Status AddWheel(const WheelSample& sample);
  void LinkGnss();
  void AttachProviders();
  Status AddImu(const ImuSample& sample);
  void TrimStreams();
  void TryInitializeInertial();
  void ApplyInertialAlignment(const InertialAlignment& alignment);
  // Initialization window (window_init.cpp).
  Stamp InitializationStart() const;
  InitWindow InitializationWindow() const;
  void Reset();
  void Restart();
  // A new LiDAR extrinsic (window_extrinsic.cpp).
  void SetLidarExtrinsic(const SE3& T_body_lidar);
  void SetWorldGravity();
  // The estimated translation (window_extrinsic.cpp): whether the run estimates it (LIO with the option);
  // whether the point-to-plane factors take it from lidar_translation (once initialized); its block and
  // prior in the graph; whether the window's turns show it.
  bool EstimatesLidarTranslation() const { return config.use_imu && config.estimate_lidar_translation; }
  bool LeverFactors() const { return EstimatesLidarTranslation() && inertial; }
  void AttachLidarTranslation();
  bool LeverExcited() const;

  // Scans (window_scans.cpp).
  // A sweep's begin and end poses: its nodes', or extrapolated for a first sweep whose motion the next scans
  // give (ExtrapolatedSweepEnds); single when it has one pose.
  struct SweepEnds {
    SE3 begin, end;
    bool single = false;
  };
  SweepEnds EndsOf(const ScanState& scan) const;
  SweepPoses Sweep(const SweepEnds& ends) const;
  SweepPoses Sweep(const ScanState& scan) const { return Sweep(EndsOf(scan)); }
  std::optional<std::pair<SE3, SE3>> ExtrapolatedSweepEnds(const ScanState& scan) const;
  void RemapFirstSweep();
  void RebuildMap();
  void Associate(ScanState& scan, Rounds rounds = {});
  const VoxelHashMap& CoarseMap();
  void InsertIntoMap(ScanState& scan);
  // Initialized LIO: the new scan's points corrected by the IMU's motion within its sweep beyond the
  // interpolation between its nodes (imu_sweep_correction.h); unchanged where the IMU has a gap.
  void CorrectSweepByImu(ScanState& scan);
  void Release(ScanState& scan);
  void ReleaseHeld(const SE3& T_world_lo);
  // A keyframe out to `finished`, or held until the estimated LiDAR translation settles
  // (window_extrinsic.cpp); ReleaseLeverHeld lets out the held ones (all of them, or the oldest beyond
  // kMaxLeverHeld).
  void Emit(Keyframe keyframe);
  void ReleaseLeverHeld(bool all);
  bool LeverSettled() const;
  void PopOldest();
  Matrix6d ScanInformation(const ScanState& scan);
  void DropWeakDirections(ScanState& scan);
  void LeaveWeakTranslationsToWheel(ScanState& scan);
  bool Project(ScanState& scan, const Matrix6d& P);  // false (nothing done) for P = I
  double ForwardSigma(const ScanState& scan) const;

  // Solve and marginalize (window_solve.cpp).
  bool Solve(int* iterations, bool new_scan_only = false, bool rigid_sweep = false);
  void Relinearize();
  void MarginalizeBefore(long keep_from, Stamp stamp);
  bool WheelScaleObservable();

  // The camera's landmarks (window_visual.cpp).
  void LinkVisual();
  std::optional<MapSurface> MapDepth(const SE3& T_world_camera, const Eigen::Vector2d& xy) const;
  std::vector<double*> AnchoredBlocks(long keep_from) const;
  void ForgetVisualBefore(long keep_from);

  // Scan flow (lidar_odometry.cpp).
  Status AddScan(const LidarScan& scan);
  void ProcessReady(bool flush);
  void ProcessScan(const LidarScan& scan);
  void StartMap(ScanState scan);

  // Registration (window_registration.cpp).
  bool RegisterNewScan(ScanState& current);
  bool RegisterRounds(ScanState& current, Rounds rounds = {});
  bool RegisterCoarseToFine(ScanState& current, bool both_kernels = false);
  double ReferenceMatchFraction() const;
  std::optional<std::string> RejectionReason(const ScanState& current, bool solved);
  struct Guess {
    std::string name;
    SE3 begin, end;             // the scan's begin and end poses
    bool both_kernels = false;  // the coarse rounds tried with both robust kernels (RegisterCoarseToFine)
  };
  std::vector<Guess> FallbackGuesses(const ScanState& current, bool poor, bool first_done);
  std::vector<Guess> TurnedGuesses();
  bool AgreesWithGuess(const ScanState& current, const SavedStates& guess);
  SE3 MoveFromGuess(const ScanState& current, const SavedStates& guess) const;
  bool GuessesTurnFar() const;
  bool MovesOffFromRest(const ScanState& current) const;
  bool SharesBeginNode(const ScanState& current) const;
  bool HoldsSweepRigid(const ScanState& current) const;
  bool FarGuess(ScanState& current);
};

}  // namespace uf::estimator
