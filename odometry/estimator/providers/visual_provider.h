// The camera's part of the window (docs/METHOD.md "Visual-inertial odometry"): it tracks the frames (the
// front end, visual/feature_tracker.h), gives the window the stamps of its nodes (a node per frame, at the
// frame's stamp + t_d), turns features seen from enough nodes into landmarks (inverse depth in the first
// observing node, the anchor, by triangulation) and links each observation to the anchor by a
// ReprojectionFactor (factors/reprojection_factor.h) under a Huber loss. It owns the blocks the factors
// share: the camera time offset t_d and T_body_camera (each free when configured, with its prior).
//
// Landmarks live until their anchor leaves the window: the window then marginalizes their inverse depths
// with the anchor (AnchoredBlocks; the inertial window), so what they said about the remaining nodes stays
// in the prior, or drops them with their factors (the LiDAR window). The oldest node is always the anchor of
// every landmark it observes, since anchors are first observations.
// After each solve, a landmark reprojecting worse than max_reprojection_px anywhere, or whose depth left
// [min_depth_m, max_depth_m], is dropped with its factors (a moving object, a bad track) and never used
// again.
//
// Two ways to give frames nodes: the inertial window makes a node per frame (NextNodeStamp, Observe); the
// LiDAR window has its nodes at the scans' boundaries and hands each frame to the node nearest its stamp +
// t_d (ObserveNearest), the factor's t_d0 then absorbing the difference. With a depth source (the LiDAR
// map, SetMapDepth) a new landmark takes its depth from where the anchor's ray meets the map, if that
// depth reprojects within max_reprojection_px in every observing camera; else it is triangulated. With
// hold_map_depth (and the extrinsic not estimated) it then stays on the map's plane there
// (factors/landmark_plane_factor.h).
//
// Reliability scheduling (visual.schedule, docs/METHOD.md "Factor-wise reliability scheduling"): a frame's
// observations wait for Link, where its tracks are held against the motion the window predicts since each
// track's previous node and scored (schedule/camera_motion_check.h); with visual.schedule.enabled, while
// the gate is shut the frame's observations are left out (its tracks still count as seen, for the next
// frame's check).
//
// Stereo (SetStereo, docs/METHOD.md "Stereo in the window"): a left frame waits until the right frame of its
// stamp comes (or the next left frame, when it goes on alone); the pair is matched (visual/stereo_matcher.h)
// and each matched feature's right observation joins the left one. A landmark whose anchor was matched starts
// (from min_track_length nodes, as any) with the pair's depth when no map depth is taken and it reprojects
// within max_reprojection_px in every observing camera; every right observation is a factor:
// StereoAnchorFactor at the anchor, ReprojectionFactor through the rig's extrinsic elsewhere.
//
// Node ids are the window's; Reset forgets every landmark (the window restarts with new ids).
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/visual_factor_config.h"
#include "odometry/estimator/factors/reprojection_factor.h"
#include "odometry/estimator/init/visual_inertial_poses.h"
#include "odometry/estimator/lidar/plane_fit.h"
#include "odometry/estimator/providers/sensor_factor_stats.h"
#include "odometry/estimator/schedule/activation_gate.h"
#include "odometry/estimator/state/window_node.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/estimator/visual/stereo_matcher.h"
#include "odometry/estimator/window/factor_graph.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

// The pose block (T_world_body) of the window's node `id`.
using PoseBlockOf = std::function<double*(long id)>;
// Where the ray of normalized coordinates (x, y) from the camera at T_world_camera meets the scene: the
// depth along the camera's z and, when the source knows it, the surface's plane there (world); or nullopt.
struct MapSurface {
  double depth = 0;
  std::optional<Plane> plane;
};
using MapDepthOf =
    std::function<std::optional<MapSurface>(const SE3& T_world_camera, const Eigen::Vector2d& xy)>;
// A node of the window: its id and stamp.
struct NodeStamp {
  long id = 0;
  Stamp stamp = 0;
};
// A stereo rig: the tracked (left) camera, the second (right) one, and the right camera in the left's frame.
struct StereoRig {
  std::shared_ptr<const CameraModel> left, right;
  SE3 T_left_right;
};

class VisualProvider {
 public:
  // Fails for a bad config or camera (the front end's checks).
  static Expected<std::unique_ptr<VisualProvider>> Create(const VisualFactorConfig& config,
                                                          const CameraModel& camera,
                                                          const SE3& T_body_camera);
  // A window's provider: none without use_camera; errors are Create's under `section` ("wio", "lio").
  static Expected<std::unique_ptr<VisualProvider>> CreateIf(bool use_camera, const VisualFactorConfig& config,
                                                            const CameraModel* camera,
                                                            const SE3& T_body_camera,
                                                            const std::string& section);
  VisualProvider(const VisualProvider&) = delete;  // the graph refers to its blocks
  VisualProvider& operator=(const VisualProvider&) = delete;
  // Makes the provider a stereo one (see above). Fails for a camera without pinhole intrinsics, a
  // non-finite extrinsic or one without a baseline.
  Status SetStereo(StereoRig rig);
  // SetStereo for a window: with visual.stereo and a right camera in its config; errors under `section`.
  Status SetStereoIf(const std::shared_ptr<const CameraModel>& left, const SE3& T_body_left,
                     const std::shared_ptr<const CameraModel>& right, const SE3& T_body_right,
                     const std::string& section);

  // Tracks a frame; its features wait for the node at stamp + t_d (with a rig, once paired). Returns the
  // front end's result (features and statistics); a frame the front end refuses (not after the last one,
  // another size) returns the reason and changes nothing. A pair that cannot be matched is a warning for the
  // next call that takes warnings.
  Expected<TrackedFrame> AddFrame(Stamp stamp, const Image& image);
  // The same for a window: the result is appended to `tracked`, a refusal or a stereo warning to
  // `warnings` ("...; frame skipped"). Returns whether the frame was taken.
  bool AddFrame(Stamp stamp, const Image& image, std::vector<TrackedFrame>& tracked,
                std::vector<std::string>& warnings);
  // A frame of the stereo rig's right camera (ignored without SetStereo); a pair that cannot be matched
  // (another size) appends a warning, and its left frame goes on alone.
  void AddRightFrame(Stamp stamp, const Image& image, std::vector<std::string>& warnings);
  // The node stamp of the first waiting frame at or after `from`, or nullopt.
  std::optional<Stamp> NextNodeStamp(Stamp from) const;

  // Registers t_d and the extrinsic with the graph, with their priors when they are free (again after the
  // graph was cleared).
  void Attach(FactorGraph& graph);
  // The waiting frame at node stamp `stamp` becomes node `id`'s observations (frames before it are
  // dropped); nothing when there is none.
  void Observe(long id, Stamp stamp);
  // The waiting frames up to the last of `nodes` (ascending ids and stamps) become the observations of the
  // node nearest their node stamp, if that node is within 60 ms and after the last node observed (a node
  // observes one frame: the first); the others are dropped. Frames after the last node wait.
  void ObserveNearest(const std::vector<NodeStamp>& nodes);
  // New landmarks take their depth from `depth` when it answers (see above).
  void SetMapDepth(MapDepthOf depth) { map_depth_ = std::move(depth); }
  // Before a solve: the frames observed since the last Link are checked and, while the gate is open, join
  // their nodes; then features seen from min_track_length nodes become landmarks when they triangulate, and
  // every new observation of a landmark gets its factor.
  void Link(FactorGraph& graph, const PoseBlockOf& pose_of);
  // After a solve: drops the outlier landmarks (see above); returns how many.
  int DropOutliers(FactorGraph& graph);
  // The inverse-depth blocks of the landmarks anchored in node `id`, to marginalize with it.
  std::vector<double*> AnchoredBlocks(long id) const;
  // Node `id` has left the window: its landmarks are forgotten.
  void ForgetNode(long id);
  // Appends the blocks a solve moves: every landmark's inverse depth, and t_d and the extrinsic when free.
  void AppendFreeBlocks(std::vector<double*>& free);
  // Forgets every landmark and observation (the graph is cleared by the caller); waiting frames stay.
  void Reset();
  // Drops the waiting frames whose node stamp is before `oldest`.
  void Trim(Stamp oldest);
  // The features of the waiting frames at these node stamps, as tracks over their indices, with the stereo
  // rig's depths (for the visual-inertial start, init/visual_inertial_poses.h).
  std::vector<FeatureTrack> Tracks(const std::vector<Stamp>& node_stamps) const;
  // Why the camera is not still over the waiting frames at these node stamps (a frame whose tracked
  // features moved more than max_static_flow_px on average since the previous frame), or nullopt.
  std::optional<std::string> NotStillReason(const std::vector<Stamp>& node_stamps) const;

  // A landmark in the graph as it stands: its feature id, anchor node, the anchor's normalized ray (at its
  // node's time) and its inverse-depth block.
  struct LandmarkView {
    long id = 0;
    long anchor = 0;
    Eigen::Vector2d normalized = Eigen::Vector2d::Zero();
    double* inverse_depth = nullptr;
  };
  std::vector<LandmarkView> Landmarks();

  double time_offset_s() const { return time_offset_; }
  // A window that drops its landmarks with their anchors (LVIO) calls this after each solve: the window's
  // t_d, when it was estimated and landmarks held it, joins the run's record (16 bytes a solve), whose median
  // weighted by the image motion behind each Report gives as the run's estimate. Each rests on the window's
  // last ~1 s of landmarks alone; VIO's prior keeps their information, so its window's t_d is the run's
  // estimate (docs/METHOD.md "LiDAR-visual-inertial odometry").
  void RecordWindowTimeOffset();
  // The mean reprojection error of the factors at the last DropOutliers (before the drops), pixels.
  double mean_reprojection_px() const { return mean_reprojection_px_; }
  int landmarks_in_graph() const;
  // The frames checked at nodes stamped up to `until` (scheduling), oldest first; earlier ones are dropped.
  std::vector<CameraCheck> TakeChecks(Stamp until);
  // Its part of the window's report: factors added, landmarks forgotten without having triangulated (the
  // parallax, depth or reprojection out of range while they were in the window), outliers.
  void Report(SensorFactorStats& stats) const;

 private:
  struct RightObservation {  // the stereo rig's right camera at the same instant
    Eigen::Vector2d normalized = Eigen::Vector2d::Zero();
    double depth_m = 0;  // the pair's triangulated depth in the left camera
  };
  using RightObservations = std::map<long, RightObservation>;  // by feature id
  struct Observation {
    long node = 0;
    FeatureObservation feature;
    double td0 = 0;  // node stamp - frame stamp, s (the factor's t_d0)
    std::optional<RightObservation> right;
  };
  struct Landmark {
    std::vector<Observation> observations;  // node order; the first is the anchor
    double inverse_depth = 0;               // the block, 1/m
    bool in_graph = false;
    bool rejected = false;  // an outlier: no factors, observations ignored
    bool untriangulated = false;  // had enough observations and failed to triangulate (so far)
    bool first_without_velocity = false;  // the first observation is the feature's first frame
    int linked = 0;                       // observations whose factors were added (AddFactors)
  };
  struct WaitingFrame {
    Stamp camera_stamp = 0;
    double td0 = 0;
    std::vector<TrackedFeature> features;
    RightObservations right;
  };
  struct PendingFrame {  // observed by a node, not yet checked and applied (Link)
    long node = 0;
    Stamp node_stamp = 0;
    double td0 = 0;
    std::vector<TrackedFeature> features;
    RightObservations right;
  };
  struct Stereo {
    StereoRig rig;
    SE3 T_right_left;
    double sqrt_information = 0;                         // the right camera's focal / pixel sigma
    std::optional<std::pair<Stamp, Image>> left, right;  // frames waiting for their partner
    std::vector<TrackedFeature> left_features;
  };

  VisualProvider(const VisualFactorConfig& config, FeatureTracker tracker, const PinholeIntrinsics& pinhole,
                 const SE3& T_body_camera);
  void ObserveFrame(long id, Stamp node_stamp, const WaitingFrame& frame, double td0);
  // The frame waits for its node (at stamp + t_d), with its stereo matches.
  void Wait(Stamp stamp, std::vector<TrackedFeature> features, const std::vector<StereoMatch>& matches);
  // Stereo: the held left frame goes on alone (its right frame never came).
  void ReleaseLeftAlone();
  // Stereo: matches the held pair when its stamps agree; a failure is a warning (stereo_warnings_).
  void MatchHeldPair();
  void TakeStereoWarnings(std::vector<std::string>& warnings);  // appends them there, and forgets them
  // Scores the pending frame against the predicted motion, updates the gate; returns whether it is active.
  bool CheckFrame(const PendingFrame& frame, const PoseBlockOf& pose_of);
  void ApplyFrame(const PendingFrame& frame);
  bool StartLandmark(FactorGraph& graph, long id, Landmark& landmark, const PoseBlockOf& pose_of);
  // The map's inverse depth for the landmark (and in `plane` the map's plane there, if the source gives
  // one), or the stereo pair's, if it reprojects within max_reprojection_px everywhere.
  std::optional<double> MapInverseDepth(const Landmark& landmark, const std::vector<SE3>& cameras,
                                        std::optional<Plane>& plane) const;
  std::optional<double> StereoInverseDepth(const Landmark& landmark, const std::vector<SE3>& cameras) const;
  std::optional<double> CheckedInverseDepth(const Landmark& landmark, const std::vector<SE3>& cameras,
                                            std::optional<double> depth) const;
  // Erases the landmark, counting it when it never triangulated.
  std::map<long, Landmark>::iterator Forget(std::map<long, Landmark>::iterator landmark);
  // Observation k's factors: its reprojection (k > 0) and its right camera's (stereo).
  void AddFactors(FactorGraph& graph, long id, Landmark& landmark, std::size_t k, const PoseBlockOf& pose_of);
  SE3 CameraPose(const double* pose_block) const;
  Eigen::Vector2d AtNodeTime(const Observation& o) const;
  double MaxReprojectionNormalized() const;

  VisualFactorConfig config_;
  FeatureTracker tracker_;
  PinholeIntrinsics pinhole_;              // the grid of the scheduling's score
  double sqrt_information_;                // focal / pixel sigma
  SE3 given_extrinsic_;                    // T_body_camera as configured
  PoseArray extrinsic_;                    // T_body_camera, pose layout (free with estimate_extrinsic)
  double time_offset_;                     // t_d, s
  std::vector<WeightedValue> window_time_offsets_;  // RecordWindowTimeOffset's: t_d, s, and its weight
  std::map<Stamp, WaitingFrame> waiting_;  // by node stamp
  std::map<long, Landmark> landmarks_;     // by feature id; std::map keeps the blocks' addresses
  MapDepthOf map_depth_;
  long last_observed_ = -1;  // ObserveNearest's last node
  std::vector<PendingFrame> pending_;      // node order
  std::map<long, Observation> last_seen_;  // by feature id: its latest observation, applied or not
  ActivationGate gate_;
  Stamp shut_at_ = 0;  // the node stamp where the gate last shut
  std::vector<CameraCheck> checks_;
  std::optional<Stereo> stereo_;
  std::vector<std::string> stereo_warnings_;  // for the next call that takes warnings
  int added_ = 0, untriangulated_ = 0, rejected_ = 0, map_depths_ = 0, map_planes_ = 0;
  int stereo_pairs_ = 0, stereo_depths_ = 0, stereo_factors_ = 0;
  double mean_reprojection_px_ = 0;
};

}  // namespace uf::estimator
