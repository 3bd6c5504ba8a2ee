#include "viewer/pipeline/splat/feature_seeds.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "odometry/estimator/lidar/voxel_key.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/estimator/visual/triangulation.h"
#include "odometry/types/camera_model.h"

namespace uf::pipeline {
namespace {

struct Observation {
  std::size_t view = 0;
  Eigen::Vector2d pixel, normalized;
};

// The map seeds hashed into cubic cells of the clearance, so the ones within it lie in the 27 cells around.
class ClearanceGrid {
 public:
  ClearanceGrid(const std::vector<Eigen::Vector3f>& points, std::size_t count, double clearance)
      : clearance_(clearance), inverse_(1 / clearance) {
    for (std::size_t i = 0; i < count; ++i)
      cells_[estimator::PackVoxelKey(estimator::VoxelOf(points[i].cast<double>(), inverse_))].push_back(
          points[i]);
  }

  bool AnyWithin(const Eigen::Vector3d& p) const {
    const estimator::VoxelIndex c = estimator::VoxelOf(p, inverse_);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(estimator::PackVoxelKey(c + estimator::VoxelIndex(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const Eigen::Vector3f& q : it->second)
            if ((q.cast<double>() - p).norm() <= clearance_) return true;
        }
    return false;
  }

 private:
  double clearance_, inverse_;
  std::unordered_map<std::uint64_t, std::vector<Eigen::Vector3f>, estimator::VoxelKeyHash> cells_;
};

// The view's colour at the pixel nearest to `pixel` (pixel centres at integers), in [0, 1].
Eigen::Vector3f ColourAt(const StoredView& view, const Eigen::Vector2d& pixel) {
  const int w = view.camera.pinhole.width, h = view.camera.pinhole.height;
  const int x = std::clamp(static_cast<int>(std::lround(pixel.x())), 0, w - 1);
  const int y = std::clamp(static_cast<int>(std::lround(pixel.y())), 0, h - 1);
  const std::uint8_t* rgb = view.rgb.data() + 3 * (static_cast<std::size_t>(y) * w + x);
  return Eigen::Vector3f(rgb[0], rgb[1], rgb[2]) / 255.0f;
}

// Every track of the training views, by feature id: the views that saw it, in time order.
Expected<std::map<long, std::vector<Observation>>> Track(const std::vector<StoredView>& train,
                                                         const FeatureSeedOptions& options) {
  PinholeRadtanIntrinsics intrinsics;
  intrinsics.pinhole = train.front().camera.pinhole;
  const PinholeRadtan camera(intrinsics);
  estimator::FeatureTrackerConfig config;
  config.max_features = options.max_features;
  config.min_distance_px = options.min_distance_px;

  Image mask;
  if (train.front().mask)
    mask = Image{intrinsics.pinhole.width, intrinsics.pinhole.height, 1, *train.front().mask};
  Expected<estimator::FeatureTracker> tracker = estimator::FeatureTracker::Create(camera, config, mask);
  if (!tracker) return Status::Error("feature seeds: " + tracker.error());
  std::map<long, std::vector<Observation>> tracks;
  for (std::size_t v = 0; v < train.size(); ++v) {
    const StoredView& view = train[v];
    Expected<estimator::TrackedFrame> frame =
        tracker->Track(view.stamp, Image{view.camera.pinhole.width, view.camera.pinhole.height, 3, view.rgb});
    if (!frame) return Status::Error("feature seeds, view " + std::to_string(v) + ": " + frame.error());
    for (const estimator::TrackedFeature& f : frame->features)
      tracks[f.id].push_back({v, f.pixel, f.normalized});
  }
  return tracks;
}

}  // namespace

Expected<FeatureSeedStats> AddFeatureSeeds(splat::GaussianModel& model, std::size_t map_seeds,
                                           const std::vector<StoredView>& train,
                                           const FeatureSeedOptions& options) {
  FeatureSeedStats stats;
  if (train.size() < 2) return stats;
  Expected<std::map<long, std::vector<Observation>>> tracks = Track(train, options);
  if (!tracks) return tracks.status();
  const ClearanceGrid map(model.positions, map_seeds, options.map_clearance_m);
  const double fx = train.front().camera.pinhole.fx;
  const float logit = static_cast<float>(std::log(options.initial_opacity / (1 - options.initial_opacity)));
  std::vector<SE3> poses;
  std::vector<Eigen::Vector2d> rays;
  for (const auto& [id, observations] : *tracks) {
    if (observations.size() < 2) continue;
    ++stats.tracks;
    poses.clear(), rays.clear();
    for (const Observation& o : observations) {
      poses.push_back(train[o.view].camera.T_world_camera);
      rays.push_back(o.normalized);
    }
    Expected<estimator::Triangulation> point =
        estimator::Triangulate(poses, rays, options.min_parallax_deg, options.min_depth_m);
    if (!point || point->max_reprojection * fx > options.max_reprojection_px) continue;
    if ((poses.front().inverse() * point->point_world).z() > options.max_depth_m) continue;
    ++stats.triangulated;
    if (map.AnyWithin(point->point_world)) {
      ++stats.near_map;
      continue;
    }
    Eigen::Vector3f colour = Eigen::Vector3f::Zero();
    for (const Observation& o : observations) colour += ColourAt(train[o.view], o.pixel);
    colour /= static_cast<float>(observations.size());
    // The corners' spacing seen from the nearest camera: min_distance_px at depth z spans z * px / fx.
    const float scale = static_cast<float>(point->min_depth_m * options.min_distance_px / fx);
    model.AddConstantColor(point->point_world.cast<float>(), Eigen::Vector3f::Constant(std::log(scale)),
                           Eigen::Quaternionf::Identity(), logit, colour);
    ++stats.added;
  }
  return stats;
}

}  // namespace uf::pipeline
