// How the camera's features become landmarks and leave as outliers (visual_provider.h): the depth a landmark
// starts with (the LiDAR map's, the stereo pair's, or triangulated), the map's plane it stays on
// (hold_map_depth), the factors of its observations, and the outlier check after a solve.
#include <ceres/loss_function.h>

#include <cmath>

#include "odometry/estimator/factors/landmark_plane_factor.h"
#include "odometry/estimator/factors/stereo_anchor_factor.h"
#include "odometry/estimator/providers/visual_provider.h"
#include "odometry/estimator/visual/triangulation.h"

namespace uf::estimator {

void VisualProvider::AddFactors(FactorGraph& graph, long id, Landmark& landmark, std::size_t k,
                                const PoseBlockOf& pose_of) {
  const Observation& anchor = landmark.observations.front();
  const Observation& target = landmark.observations[k];
  const std::vector<double*> blocks = {pose_of(anchor.node), pose_of(target.node), extrinsic_.data(),
                                       &landmark.inverse_depth, &time_offset_};
  auto loss = [&] { return std::make_unique<ceres::HuberLoss>(config_.huber_sigmas); };
  if (k > 0) {
    graph.Add(FactorKind::kVisual, id,
              std::make_unique<ReprojectionFactor>(anchor.feature, target.feature, anchor.td0, target.td0,
                                                   sqrt_information_),
              loss(), blocks);
    ++added_;
  }
  if (!stereo_ || !target.right) return;
  // The right camera sees the feature with the anchor camera's image velocity (a rig moves as one).
  const FeatureObservation right{target.right->normalized, target.feature.velocity};
  if (k == 0) {
    graph.Add(FactorKind::kVisual, id,
              std::make_unique<StereoAnchorFactor>(anchor.feature, right.normalized, anchor.td0,
                                                   stereo_->sqrt_information, stereo_->T_right_left),
              loss(), {&landmark.inverse_depth, &time_offset_});
  } else {
    graph.Add(FactorKind::kVisual, id,
              std::make_unique<ReprojectionFactor>(anchor.feature, right, anchor.td0, target.td0,
                                                   stereo_->sqrt_information, stereo_->T_right_left),
              loss(), blocks);
  }
  ++added_;
  ++stereo_factors_;
}

std::optional<double> VisualProvider::MapInverseDepth(const Landmark& landmark,
                                                      const std::vector<SE3>& cameras,
                                                      std::optional<Plane>& plane) const {
  const std::optional<MapSurface> surface =
      map_depth_(cameras.front(), AtNodeTime(landmark.observations.front()));
  if (!surface) return std::nullopt;
  const std::optional<double> inverse_depth = CheckedInverseDepth(landmark, cameras, surface->depth);
  if (inverse_depth) plane = surface->plane;
  return inverse_depth;
}

std::optional<double> VisualProvider::CheckedInverseDepth(const Landmark& landmark,
                                                          const std::vector<SE3>& cameras,
                                                          std::optional<double> depth) const {
  const Eigen::Vector2d xy = AtNodeTime(landmark.observations.front());
  if (!depth || !(*depth >= config_.min_depth_m && *depth <= config_.max_depth_m)) return std::nullopt;
  const Eigen::Vector3d point = cameras.front() * (*depth * xy.homogeneous());
  const double max_normalized = MaxReprojectionNormalized();
  for (std::size_t k = 1; k < cameras.size(); ++k) {
    const Eigen::Vector3d p = cameras[k].inverse() * point;
    if (!(p.z() >= config_.min_depth_m)) return std::nullopt;
    if (!((p.hnormalized() - AtNodeTime(landmark.observations[k])).norm() <= max_normalized))
      return std::nullopt;
  }
  return 1.0 / *depth;
}

// Takes the map's depth or the stereo pair's (see the top of the header), else triangulates the landmark
// from the current camera poses of its nodes; in range, it joins the graph (Link adds its factors).
bool VisualProvider::StartLandmark(FactorGraph& graph, long id, Landmark& landmark,
                                   const PoseBlockOf& pose_of) {
  std::vector<SE3> cameras;
  std::vector<Eigen::Vector2d> rays;
  for (const Observation& o : landmark.observations) {
    cameras.push_back(CameraPose(pose_of(o.node)));
    rays.push_back(AtNodeTime(o));
  }
  std::optional<Plane> plane;
  std::optional<double> inverse_depth = map_depth_ ? MapInverseDepth(landmark, cameras, plane) : std::nullopt;
  if (inverse_depth) {
    ++map_depths_;
  } else if ((inverse_depth = StereoInverseDepth(landmark, cameras))) {
    ++stereo_depths_;
  } else {
    Expected<Triangulation> point = Triangulate(cameras, rays, config_.min_parallax_deg, config_.min_depth_m);
    if (!point) return false;
    inverse_depth = InverseDepth(cameras.front(), point->point_world);
    if (!(*inverse_depth >= 1.0 / config_.max_depth_m) ||
        point->max_reprojection > MaxReprojectionNormalized())
      return false;
  }
  landmark.inverse_depth = *inverse_depth;
  graph.AddEuclideanBlock(&landmark.inverse_depth, 1);
  // The map's plane keeps the depth, where the ray that found it can be trusted: with the extrinsic
  // estimated, the rays turn as it converges, and the planes they met are not where the features lie.
  if (plane && config_.hold_map_depth && !config_.estimate_extrinsic && plane->sigma > 0) {
    const Observation& anchor = landmark.observations.front();
    graph.Add(FactorKind::kVisual, id,
              std::make_unique<LandmarkPlaneFactor>(anchor.feature, anchor.td0, *plane),
              std::make_unique<ceres::HuberLoss>(config_.huber_sigmas),
              {pose_of(anchor.node), extrinsic_.data(), &landmark.inverse_depth, &time_offset_});
    ++map_planes_;
  }
  landmark.in_graph = true;
  landmark.linked = 0;
  return true;
}

void VisualProvider::Link(FactorGraph& graph, const PoseBlockOf& pose_of) {
  for (const PendingFrame& frame : pending_)
    if (CheckFrame(frame, pose_of)) ApplyFrame(frame);
  pending_.clear();
  const std::size_t needed = static_cast<std::size_t>(std::max(2, config_.tracker.min_track_length));
  for (auto& [id, landmark] : landmarks_) {
    if (landmark.rejected) continue;
    if (!landmark.in_graph) {
      if (landmark.observations.size() < needed) continue;
      landmark.untriangulated = !StartLandmark(graph, id, landmark, pose_of);
      if (landmark.untriangulated) continue;
    }
    for (std::size_t k = static_cast<std::size_t>(landmark.linked); k < landmark.observations.size(); ++k)
      AddFactors(graph, id, landmark, k, pose_of);
    landmark.linked = static_cast<int>(landmark.observations.size());
  }
}

int VisualProvider::DropOutliers(FactorGraph& graph) {
  std::map<long, double> worst_px;  // by landmark: its largest reprojection error
  double sum_px = 0;
  int count = 0;
  for (const Factor& f : graph.Entries(FactorKind::kVisual)) {
    if (f.tag < 0 || f.cost->num_residuals() != 2) continue;  // the priors, the map planes
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

}  // namespace uf::estimator
