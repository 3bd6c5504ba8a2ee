#include "odometry/estimator/providers/visual_provider.h"

#include <ceres/loss_function.h>

#include <algorithm>
#include <cmath>

#include "odometry/estimator/factors/wheel_factor.h"
#include "odometry/estimator/visual/triangulation.h"
#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

constexpr long kTimeOffsetPriorTag = -1;

}  // namespace

Expected<std::unique_ptr<VisualProvider>> VisualProvider::Create(const VisualFactorConfig& config,
                                                                 const CameraModel& camera,
                                                                 const SE3& T_body_camera) {
  if (Status s = config.Validate(); !s.ok()) return s;
  Expected<FeatureTracker> tracker = FeatureTracker::Create(camera, config.tracker);
  if (!tracker) return tracker.status();
  const PinholeIntrinsics pinhole = *PinholeOf(camera);  // the tracker checked that there is one
  // One sqrt-information for both axes: the normalized residual times the mean focal length is in pixels.
  const double focal_px = 0.5 * (pinhole.fx + pinhole.fy);
  return std::unique_ptr<VisualProvider>(
      new VisualProvider(config, std::move(*tracker), focal_px, T_body_camera));
}

VisualProvider::VisualProvider(const VisualFactorConfig& config, FeatureTracker tracker, double focal_px,
                               const SE3& T_body_camera)
    : config_(config),
      tracker_(std::move(tracker)),
      sqrt_information_(focal_px / config.pixel_sigma_px),
      extrinsic_(PoseBlock(T_body_camera)),
      time_offset_(config.time_offset_s) {}

Expected<TrackedFrame> VisualProvider::AddFrame(Stamp stamp, const Image& image) {
  Expected<TrackedFrame> tracked = tracker_.Track(stamp, image);
  if (!tracked) return tracked.status();
  const Stamp node_stamp = stamp + FromSeconds(time_offset_);
  waiting_[node_stamp] = {stamp, ToSeconds(node_stamp - stamp), tracked->features};
  return tracked;
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
}

// Every feature of the frame is observed by the node; a landmark (not yet in the graph) whose feature the
// frame lost can never reach min_track_length nodes again and is forgotten.
void VisualProvider::Observe(long id, Stamp stamp) {
  auto frame = waiting_.find(stamp);
  if (frame == waiting_.end()) return;
  std::map<long, const TrackedFeature*> seen;
  for (const TrackedFeature& feature : frame->second.features) seen[feature.id] = &feature;
  for (auto it = landmarks_.begin(); it != landmarks_.end();)
    it = !it->second.in_graph && !it->second.rejected && !seen.count(it->first) ? Forget(it) : std::next(it);
  for (const auto& [feature_id, feature] : seen) {
    Landmark& landmark = landmarks_[feature_id];
    if (landmark.rejected) continue;
    landmark.observations.push_back({id, {feature->normalized, feature->velocity}, frame->second.td0});
  }
  waiting_.erase(waiting_.begin(), std::next(frame));
}

SE3 VisualProvider::CameraPose(const double* pose_block) const {
  return PoseFromBlock(pose_block) * PoseFromBlock(extrinsic_.data());
}

void VisualProvider::AddFactor(FactorGraph& graph, long id, Landmark& landmark, std::size_t k,
                               const PoseBlockOf& pose_of) {
  const Observation& anchor = landmark.observations.front();
  const Observation& target = landmark.observations[k];
  graph.Add(FactorKind::kVisual, id,
            std::make_unique<ReprojectionFactor>(anchor.feature, target.feature, anchor.td0, target.td0,
                                                 sqrt_information_),
            std::make_unique<ceres::HuberLoss>(config_.huber_sigmas),
            {pose_of(anchor.node), pose_of(target.node), extrinsic_.data(), &landmark.inverse_depth,
             &time_offset_});
  ++added_;
}

// Triangulates the landmark from the current camera poses of its nodes; in range, it joins the graph with a
// factor per observation after the anchor.
bool VisualProvider::StartLandmark(FactorGraph& graph, Landmark& landmark, const PoseBlockOf& pose_of) {
  std::vector<SE3> cameras;
  std::vector<Eigen::Vector2d> rays;
  for (const Observation& o : landmark.observations) {
    cameras.push_back(CameraPose(pose_of(o.node)));
    rays.push_back(o.feature.normalized);
  }
  Expected<Triangulation> point = Triangulate(cameras, rays, config_.min_parallax_deg, config_.min_depth_m);
  if (!point) return false;
  const double inverse_depth = InverseDepth(cameras.front(), point->point_world);
  if (!(inverse_depth >= 1.0 / config_.max_depth_m) ||
      point->max_reprojection * sqrt_information_ * config_.pixel_sigma_px > config_.max_reprojection_px)
    return false;
  landmark.inverse_depth = inverse_depth;
  graph.AddEuclideanBlock(&landmark.inverse_depth, 1);
  landmark.in_graph = true;
  landmark.linked = 1;
  return true;
}

void VisualProvider::Link(FactorGraph& graph, const PoseBlockOf& pose_of) {
  const std::size_t needed = static_cast<std::size_t>(std::max(2, config_.tracker.min_track_length));
  for (auto& [id, landmark] : landmarks_) {
    if (landmark.rejected) continue;
    if (!landmark.in_graph) {
      if (landmark.observations.size() < needed) continue;
      landmark.untriangulated = !StartLandmark(graph, landmark, pose_of);
      if (landmark.untriangulated) continue;
    }
    for (std::size_t k = static_cast<std::size_t>(landmark.linked); k < landmark.observations.size(); ++k)
      AddFactor(graph, id, landmark, k, pose_of);
    landmark.linked = static_cast<int>(landmark.observations.size());
  }
}

int VisualProvider::DropOutliers(FactorGraph& graph) {
  std::map<long, double> worst_px;  // by landmark: its largest reprojection error
  double sum_px = 0;
  int count = 0;
  for (const Factor& f : graph.Entries(FactorKind::kVisual)) {
    if (f.tag == kTimeOffsetPriorTag) continue;
    double r[2];
    if (!f.cost->Evaluate(f.blocks.data(), r, nullptr)) r[0] = r[1] = INFINITY;
    const double px = std::hypot(r[0], r[1]) * config_.pixel_sigma_px;
    double& worst = worst_px[f.tag];
    worst = std::isfinite(px) ? std::max(worst, px) : INFINITY;
    if (std::isfinite(px)) {
      sum_px += px;
      ++count;
    }
  }
  mean_reprojection_px_ = count > 0 ? sum_px / count : 0;
  int dropped = 0;
  for (auto& [id, landmark] : landmarks_) {
    if (!landmark.in_graph) continue;
    const double depth = 1.0 / landmark.inverse_depth;
    const auto worst = worst_px.find(id);
    const bool outlier = !(depth >= config_.min_depth_m && depth <= config_.max_depth_m) ||
                         (worst != worst_px.end() && !(worst->second <= config_.max_reprojection_px));
    if (!outlier) continue;
    graph.RemoveBlocks({&landmark.inverse_depth});
    landmark.in_graph = false;
    landmark.rejected = true;
    ++dropped;
  }
  rejected_ += dropped;
  return dropped;
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
  for (auto it = landmarks_.begin(); it != landmarks_.end();)
    it = !it->second.observations.empty() && it->second.observations.front().node <= id ? Forget(it)
                                                                                        : std::next(it);
}

void VisualProvider::AppendFreeBlocks(std::vector<double*>& free) {
  for (auto& [id, landmark] : landmarks_)
    if (landmark.in_graph) free.push_back(&landmark.inverse_depth);
  if (config_.estimate_time_offset) free.push_back(&time_offset_);
}

void VisualProvider::Reset() { landmarks_.clear(); }

std::optional<std::string> VisualProvider::NotStillReason(const std::vector<Stamp>& node_stamps) const {
  for (Stamp stamp : node_stamps) {
    const auto frame = waiting_.find(stamp);
    if (frame == waiting_.end()) continue;
    double sum = 0;
    int tracked = 0;
    for (const TrackedFeature& f : frame->second.features)
      if (f.length > 1) {
        sum += (f.pixel - f.previous_pixel).norm();
        ++tracked;
      }
    if (tracked > 0 && sum / tracked > config_.max_static_flow_px)
      return PrintfText("the camera moves (features %.2f px per frame at ", sum / tracked) +
             StampText(frame->second.camera_stamp) +
             PrintfText(", above visual.max_static_flow_px %.2f)", config_.max_static_flow_px);
  }
  return std::nullopt;
}

void VisualProvider::Trim(Stamp oldest) { waiting_.erase(waiting_.begin(), waiting_.lower_bound(oldest)); }

std::vector<VisualProvider::LandmarkView> VisualProvider::Landmarks() {
  std::vector<LandmarkView> views;
  for (auto& [id, landmark] : landmarks_)
    if (landmark.in_graph) {
      const Observation& anchor = landmark.observations.front();
      views.push_back({id, anchor.node, anchor.feature.normalized, &landmark.inverse_depth});
    }
  return views;
}

int VisualProvider::landmarks_in_graph() const {
  return static_cast<int>(
      std::count_if(landmarks_.begin(), landmarks_.end(), [](const auto& l) { return l.second.in_graph; }));
}

void VisualProvider::Report(SensorFactorStats& stats) const {
  stats.visual = {added_, untriangulated_, rejected_};
  stats.camera_time_offset_s = time_offset_;
}

}  // namespace uf::estimator
