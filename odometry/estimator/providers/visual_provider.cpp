#include "odometry/estimator/providers/visual_provider.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "odometry/estimator/factors/pose_prior_factor.h"
#include "odometry/estimator/factors/wheel_factor.h"

namespace uf::estimator {
namespace {

// The tags of the priors on t_d and the extrinsic; a landmark's factors carry its (non-negative) id.
constexpr long kTimeOffsetPriorTag = -1;
constexpr long kExtrinsicPriorTag = -2;
// ObserveNearest: a frame farther than this from every node is dropped. The factor moves each feature to its
// node's time along its image velocity (reprojection_factor.h), a first-order step that holds over the half
// sweep (50 ms at 10 Hz) between a frame in mid-sweep and the scan's nodes, not over the gaps of keyframe
// data.
constexpr Stamp kMaxNodeDistance = 60'000'000;  // 60 ms

}  // namespace

Expected<std::unique_ptr<VisualProvider>> VisualProvider::Create(const VisualFactorConfig& config,
                                                                 const CameraModel& camera,
                                                                 const SE3& T_body_camera) {
  if (Status s = config.Validate(); !s.ok()) return s;
  Expected<FeatureTracker> tracker = FeatureTracker::Create(camera, config.tracker);
  if (!tracker) return tracker.status();
  const PinholeIntrinsics pinhole = *PinholeOf(camera);  // the tracker checked that there is one
  return std::unique_ptr<VisualProvider>(
      new VisualProvider(config, std::move(*tracker), pinhole, T_body_camera));
}

Expected<std::unique_ptr<VisualProvider>> VisualProvider::CreateIf(bool use_camera,
                                                                   const VisualFactorConfig& config,
                                                                   const CameraModel* camera,
                                                                   const SE3& T_body_camera,
                                                                   const std::string& section) {
  if (!use_camera) return std::unique_ptr<VisualProvider>();
  if (!camera) return Status::Error(section + ".visual: no camera model");
  Expected<std::unique_ptr<VisualProvider>> made = Create(config, *camera, T_body_camera);
  if (!made) return Status::Error(section + ".visual: " + made.status().message());
  return made;
}

// One sqrt-information for both axes: the normalized residual times the mean focal length is in pixels.
VisualProvider::VisualProvider(const VisualFactorConfig& config, FeatureTracker tracker,
                               const PinholeIntrinsics& pinhole, const SE3& T_body_camera)
    : config_(config),
      tracker_(std::move(tracker)),
      pinhole_(pinhole),
      sqrt_information_(0.5 * (pinhole.fx + pinhole.fy) / config.pixel_sigma_px),
      given_extrinsic_(T_body_camera),
      extrinsic_(PoseBlock(T_body_camera)),
      time_offset_(config.time_offset_s),
      gate_({config.schedule.threshold, config.schedule.release_margin, config.schedule.release_frames,
             config.schedule.min_tracks}) {}

Expected<TrackedFrame> VisualProvider::AddFrame(Stamp stamp, const Image& image) {
  Expected<TrackedFrame> tracked = tracker_.Track(stamp, image);
  if (!tracked) return tracked.status();
  if (!stereo_) {
    Wait(stamp, tracked->features, {});
    return tracked;
  }
  ReleaseLeftAlone();
  stereo_->left.emplace(stamp, image);
  stereo_->left_features = tracked->features;
  MatchHeldPair();
  return tracked;
}

bool VisualProvider::AddFrame(Stamp stamp, const Image& image, std::vector<TrackedFrame>& tracked,
                              std::vector<std::string>& warnings) {
  Expected<TrackedFrame> frame = AddFrame(stamp, image);
  if (!frame) {
    warnings.push_back(frame.status().message() + "; frame skipped");
    return false;
  }
  tracked.push_back(std::move(*frame));
  TakeStereoWarnings(warnings);
  return true;
}

void VisualProvider::Wait(Stamp stamp, std::vector<TrackedFeature> features,
                          const std::vector<StereoMatch>& matches) {
  const Stamp node_stamp = stamp + FromSeconds(time_offset_);
  WaitingFrame& frame =
      waiting_[node_stamp] = {stamp, ToSeconds(node_stamp - stamp), std::move(features), {}};
  for (const StereoMatch& m : matches) frame.right[m.id] = {m.right_normalized, m.depth_m};
}

std::optional<Stamp> VisualProvider::NextNodeStamp(Stamp from) const {
  const auto it = waiting_.lower_bound(from);
  if (it == waiting_.end()) return std::nullopt;
  return it->first;
}

void VisualProvider::Attach(FactorGraph& graph) {
  graph.AddPoseBlock(extrinsic_.data());
  graph.AddEuclideanBlock(&time_offset_, 1);
  if (config_.estimate_time_offset)  // a scalar prior: r = (t_d - start) / sigma
    graph.Add(FactorKind::kVisual, kTimeOffsetPriorTag,
              std::make_unique<WheelScalePriorFactor>(config_.time_offset_sigma_s, config_.time_offset_s),
              nullptr, {&time_offset_});
  if (config_.estimate_extrinsic)
    graph.Add(FactorKind::kVisual, kExtrinsicPriorTag,
              MakePosePriorFactor(given_extrinsic_, config_.extrinsic_translation_sigma_m,
                                  config_.extrinsic_rotation_sigma_deg * std::numbers::pi / 180),
              nullptr, {extrinsic_.data()});
}

void VisualProvider::Observe(long id, Stamp stamp) {
  auto frame = waiting_.find(stamp);
  if (frame == waiting_.end()) return;
  ObserveFrame(id, stamp, frame->second, frame->second.td0);
  waiting_.erase(waiting_.begin(), std::next(frame));
}

void VisualProvider::ObserveNearest(const std::vector<NodeStamp>& nodes) {
  if (nodes.empty()) return;
  std::size_t k = 0;  // the node nearest the frame
  while (!waiting_.empty() && waiting_.begin()->first <= nodes.back().stamp) {
    const auto& [node_stamp, frame] = *waiting_.begin();
    while (k + 1 < nodes.size() && nodes[k + 1].stamp - node_stamp < node_stamp - nodes[k].stamp) ++k;
    if (nodes[k].id > last_observed_ && std::llabs(nodes[k].stamp - node_stamp) <= kMaxNodeDistance) {
      ObserveFrame(nodes[k].id, nodes[k].stamp, frame, ToSeconds(nodes[k].stamp - frame.camera_stamp));
      last_observed_ = nodes[k].id;
    }
    waiting_.erase(waiting_.begin());
  }
}

void VisualProvider::ObserveFrame(long id, Stamp node_stamp, const WaitingFrame& frame, double td0) {
  pending_.push_back({id, node_stamp, td0, frame.features, frame.right});
}

// Every feature of the frame is observed by the node; a landmark (not yet in the graph) whose feature the
// frame lost can never reach min_track_length nodes again and is forgotten. A feature's first frame has no
// velocity (the front end's is since the previous frame); its second frame's, the motion between the two,
// stands in for it, so that the anchor too moves to its node's time (reprojection_factor.h).
void VisualProvider::ApplyFrame(const PendingFrame& frame) {
  const long id = frame.node;
  const double td0 = frame.td0;
  std::map<long, const TrackedFeature*> seen;
  for (const TrackedFeature& feature : frame.features) seen[feature.id] = &feature;
  for (auto it = landmarks_.begin(); it != landmarks_.end();)
    it = !it->second.in_graph && !it->second.rejected && !seen.count(it->first) ? Forget(it) : std::next(it);
  for (const auto& [feature_id, feature] : seen) {
    Landmark& landmark = landmarks_[feature_id];
    if (landmark.rejected) continue;
    if (landmark.observations.size() == 1 && landmark.first_without_velocity)
      landmark.observations.front().feature.velocity = feature->velocity;
    if (landmark.observations.empty()) landmark.first_without_velocity = feature->length <= 1;
    const auto right = frame.right.find(feature_id);
    landmark.observations.push_back(
        {id,
         {feature->normalized, feature->velocity},
         td0,
         right != frame.right.end() ? std::optional(right->second) : std::nullopt});
  }
}

// max_reprojection_px in normalized units: over the focal length (sqrt_information_ = focal / pixel_sigma).
double VisualProvider::MaxReprojectionNormalized() const {
  return config_.max_reprojection_px / (sqrt_information_ * config_.pixel_sigma_px);
}

// The feature moved to its node's time for the current t_d, as the factor does (reprojection_factor.h).
Eigen::Vector2d VisualProvider::AtNodeTime(const Observation& o) const {
  return o.feature.normalized - (time_offset_ - o.td0) * o.feature.velocity;
}

SE3 VisualProvider::CameraPose(const double* pose_block) const {
  return PoseFromBlock(pose_block) * PoseFromBlock(extrinsic_.data());
}

std::vector<double*> VisualProvider::AnchoredBlocks(long id) const {
  std::vector<double*> blocks;
  for (const auto& [feature_id, landmark] : landmarks_)
    if (landmark.in_graph && landmark.observations.front().node == id)
      blocks.push_back(const_cast<double*>(&landmark.inverse_depth));
  return blocks;
}

std::map<long, VisualProvider::Landmark>::iterator VisualProvider::Forget(
    std::map<long, Landmark>::iterator landmark) {
  if (landmark->second.untriangulated) ++untriangulated_;
  return landmarks_.erase(landmark);
}

void VisualProvider::ForgetNode(long id) {
  std::erase_if(pending_, [id](const PendingFrame& frame) { return frame.node <= id; });
  std::erase_if(last_seen_, [id](const auto& seen) { return seen.second.node <= id; });
  for (auto it = landmarks_.begin(); it != landmarks_.end();)
    it = !it->second.observations.empty() && it->second.observations.front().node <= id ? Forget(it)
                                                                                        : std::next(it);
}

void VisualProvider::AppendFreeBlocks(std::vector<double*>& free) {
  for (auto& [id, landmark] : landmarks_)
    if (landmark.in_graph) free.push_back(&landmark.inverse_depth);
  if (config_.estimate_time_offset) free.push_back(&time_offset_);
  if (config_.estimate_extrinsic) free.push_back(extrinsic_.data());
}

void VisualProvider::Reset() {
  landmarks_.clear();
  pending_.clear();
  last_seen_.clear();
  gate_.Open();
  last_observed_ = -1;
}

void VisualProvider::Trim(Stamp oldest) { waiting_.erase(waiting_.begin(), waiting_.lower_bound(oldest)); }

std::vector<VisualProvider::LandmarkView> VisualProvider::Landmarks() {
  std::vector<LandmarkView> views;
  for (auto& [id, landmark] : landmarks_)
    if (landmark.in_graph) {
      const Observation& anchor = landmark.observations.front();
      views.push_back({id, anchor.node, AtNodeTime(anchor), &landmark.inverse_depth});
    }
  return views;
}

int VisualProvider::landmarks_in_graph() const {
  return static_cast<int>(
      std::count_if(landmarks_.begin(), landmarks_.end(), [](const auto& l) { return l.second.in_graph; }));
}

// The weight of the window's t_d: the information its landmarks' observations give t_d with every other
// block held, sum (s |v|)^2 over them (dr/dt_d = s v, s = focal / pixel sigma, v the feature's image velocity
// in normalized coordinates per second). A window at rest or crawling, whose features barely move, says
// little about t_d, and its estimate counts for as little.
void VisualProvider::RecordWindowTimeOffset() {
  if (!config_.estimate_time_offset) return;
  double information = 0;
  for (const auto& [id, landmark] : landmarks_) {
    if (!landmark.in_graph) continue;
    const std::size_t linked = std::min<std::size_t>(landmark.linked, landmark.observations.size());
    for (std::size_t k = 0; k < linked; ++k)
      information += landmark.observations[k].feature.velocity.squaredNorm();
  }
  information *= sqrt_information_ * sqrt_information_;
  if (information > 0) window_time_offsets_.push_back({time_offset_, information});
}

void VisualProvider::Report(SensorFactorStats& stats) const {
  stats.visual = {added_, untriangulated_, rejected_};
  stats.camera_time_offset_s = stats.camera_time_offset_window_s = time_offset_;
  stats.camera_time_offset_estimates = static_cast<int>(window_time_offsets_.size());
  if (!window_time_offsets_.empty()) {
    std::vector<WeightedValue> sorted = window_time_offsets_;
    std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.value < b.value; });
    stats.camera_time_offset_s = WeightedRank(sorted, 0.5);
    stats.camera_time_offset_iqr_s = WeightedRank(sorted, 0.75) - WeightedRank(sorted, 0.25);
  }
  stats.visual_map_depths = map_depths_;
  stats.visual_map_planes = map_planes_;
  stats.stereo_pairs = stereo_pairs_;
  stats.stereo_depths = stereo_depths_;
  stats.stereo_factors = stereo_factors_;
  if (config_.estimate_extrinsic) stats.camera_extrinsic = PoseFromBlock(extrinsic_.data());
}

}  // namespace uf::estimator
