// bench_map_bias: the pull of one registration against the LiDAR map along the track and about the
// vertical, apart from the odometry (docs/METHOD.md "Along-track scale of the registration"). Every scan of
// a recording with ground truth is placed at its true poses (each point at the pose of its own time: no
// deskew error), its registration points are matched to the map of the scans before it (lo.map's planes,
// the window's correspondence gate and Huber loss), and one Gauss-Newton step of the rigid scan is taken
// from the truth:
//   r_i = n_i^T (p_i - q_i),   J_i = [n_i^T, ((p_i - c) x n_i)^T]      (translation, rotation about c)
//   w_i = min(1, huber / |r_i|) / sigma_i^2,   delta = -H^-1 sum_i w_i r_i J_i,   H = sum_i w_i J_i^T J_i
// with c the scan's middle position. On an unbiased map delta is zero on average. Its component along the
// direction of travel, summed over the scans and divided by the distance travelled, is the scale one
// registration pulls towards (ppm); its rotation about the world's vertical, likewise, the heading (urad per
// scan and per m). The odometry drifts by a fraction of them: each scan registers against map points placed
// by earlier registrations, which carry the same pull. Both are split by the surface the point's plane
// belongs to (by its normal: ground, facing the direction of travel, lateral to it, oblique) and by range,
// each part mapped through the whole scan's H, so the parts add up. Figures are printed, not asserted.
//   usage: bench_map_bias SEQUENCE [--voxel M] [--insert-voxel M] [--max-points N] [--neighbour-weight W]
//            [--eigen-ratio R] [--huber M] [--rings N] [--downsample random|first|last|shuffled|nearest]
//            [--view-bins N]
// --downsample: which point of a voxel the scan keeps: random (the estimator's DownsamplePrepared), the
// first or the last in acquisition order, another random draw (shuffled), or the one nearest the voxel's
// centre. --view-bins N: the map split into N maps by the horizontal direction a point was seen from, each
// query answered by the map of its own direction (else by the whole map): a map that keeps each surface's
// sides apart.
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/estimator/lidar/voxel_key.h"
#include "odometry/estimator/lidar_odometry/scan_preparation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/trajectory_file.h"

namespace {

using uf::estimator::PreparedPoint;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct Options {
  std::string sequence;
  double input_voxel_m = 0.5, insert_voxel_m = 0.5;  // configs/run-sim.yaml
  double huber_m = 0.1, max_plane_distance_m = 1.0, min_range_m = 1.0, max_range_m = 100.0;
  uf::estimator::VoxelMapConfig map;
  std::string downsample = "random";
  int view_bins = 0;
};

bool Parse(int argc, char** argv, Options* options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--voxel" && has_value) {
      options->input_voxel_m = std::atof(argv[++i]);
    } else if (arg == "--insert-voxel" && has_value) {
      options->insert_voxel_m = std::atof(argv[++i]);
    } else if (arg == "--max-points" && has_value) {
      options->map.max_points_per_voxel = std::atoi(argv[++i]);
    } else if (arg == "--neighbour-weight" && has_value) {
      options->map.neighbour_weight = std::atof(argv[++i]);
    } else if (arg == "--eigen-ratio" && has_value) {
      options->map.plane_eigen_ratio = std::atof(argv[++i]);
    } else if (arg == "--huber" && has_value) {
      options->huber_m = std::atof(argv[++i]);
    } else if (arg == "--rings" && has_value) {
      options->map.min_plane_rings = std::atoi(argv[++i]);
    } else if (arg == "--downsample" && has_value) {
      options->downsample = argv[++i];
    } else if (arg == "--view-bins" && has_value) {
      options->view_bins = std::atoi(argv[++i]);
    } else if (!arg.empty() && arg[0] != '-' && options->sequence.empty()) {
      options->sequence = arg;
    } else {
      return false;
    }
  }
  const bool rule = options->downsample == "random" || options->downsample == "first" ||
                    options->downsample == "last" || options->downsample == "shuffled" ||
                    options->downsample == "nearest";
  return !options->sequence.empty() && rule && options->view_bins >= 0 && options->input_voxel_m > 0 &&
         options->insert_voxel_m > 0 && options->huber_m > 0 && options->map.Validate().ok();
}

// One point per voxel of the lidar frame, by `rule` (Options::downsample).
std::vector<PreparedPoint> Downsample(const std::vector<PreparedPoint>& points, double voxel_m,
                                      const std::string& rule, std::mt19937& engine) {
  if (rule == "random") return uf::estimator::DownsamplePrepared(points, voxel_m);
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  std::vector<std::uint64_t> order;  // of first appearance
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto key =
        uf::estimator::PackVoxelKey(uf::estimator::VoxelOf(points[i].point_lidar, 1.0 / voxel_m));
    auto& cell = cells[key];
    if (cell.empty()) order.push_back(key);
    cell.push_back(i);
  }
  std::vector<PreparedPoint> out;
  out.reserve(order.size());
  for (const std::uint64_t key : order) {
    const auto& cell = cells[key];
    std::size_t pick = rule == "first" ? cell.front() : cell.back();
    if (rule == "shuffled") {
      pick = cell[std::uniform_int_distribution<std::size_t>(0, cell.size() - 1)(engine)];
    } else if (rule == "nearest") {
      double best = INFINITY;
      for (const std::size_t i : cell) {
        const Eigen::Vector3d p = points[i].point_lidar / voxel_m;
        const double distance = (p - (p.array().floor() + 0.5).matrix()).squaredNorm();
        if (distance < best) best = distance, pick = i;
      }
    }
    out.push_back(points[pick]);
  }
  return out;
}

// The map, or one map per horizontal viewing direction (Options::view_bins) beside it.
class Maps {
 public:
  explicit Maps(const Options& options)
      : whole_(options.map), views_(options.view_bins, uf::estimator::VoxelHashMap(options.map)) {}

  std::optional<uf::estimator::Plane> PlaneNear(const Eigen::Vector3d& point,
                                                const Eigen::Vector3d& sensor) const {
    if (!views_.empty())
      if (auto plane = views_[BinOf(point, sensor)].PlaneNear(point)) return plane;
    return whole_.PlaneNear(point);
  }
  void Insert(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& rings,
              const Eigen::Vector3d& sensor) {
    whole_.Insert(points, rings);
    whole_.RemoveFarFrom(sensor);
    if (views_.empty()) return;
    std::vector<std::vector<Eigen::Vector3d>> binned(views_.size());
    std::vector<std::vector<int>> binned_rings(views_.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const int bin = BinOf(points[i], sensor);
      binned[bin].push_back(points[i]);
      binned_rings[bin].push_back(rings[i]);
    }
    for (std::size_t bin = 0; bin < views_.size(); ++bin) {
      views_[bin].Insert(binned[bin], binned_rings[bin]);
      views_[bin].RemoveFarFrom(sensor);
    }
  }

 private:
  int BinOf(const Eigen::Vector3d& point, const Eigen::Vector3d& sensor) const {
    const Eigen::Vector3d d = point - sensor;
    const double turn = (std::atan2(d.y(), d.x()) + std::numbers::pi) / (2 * std::numbers::pi);
    return std::min(static_cast<int>(views_.size()) - 1, static_cast<int>(turn * views_.size()));
  }
  uf::estimator::VoxelHashMap whole_;
  std::vector<uf::estimator::VoxelHashMap> views_;
};

// The parts of the pull: surface (by the plane's normal n against the direction of travel f) x range.
constexpr int kSurfaces = 4, kBands = 3;
constexpr const char* kSurfaceNames[kSurfaces] = {"ground (|n_z| > 0.8)", "facing (|n.f| > 0.8)",
                                                  "lateral (|n.f| < 0.2)", "oblique (the rest)"};
int SurfaceOf(const Eigen::Vector3d& normal, const Eigen::Vector3d& forward) {
  const double along = std::abs(normal.dot(forward));
  return std::abs(normal.z()) > 0.8 ? 0 : along > 0.8 ? 1 : along < 0.2 ? 2 : 3;
}
int BandOf(double range) { return range < 10 ? 0 : range < 30 ? 1 : 2; }

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!Parse(argc, argv, &options)) {
    std::fprintf(stderr,
                 "usage: bench_map_bias SEQUENCE [--voxel M] [--insert-voxel M] [--max-points N] "
                 "[--neighbour-weight W] [--eigen-ratio R] [--huber M] [--rings N] "
                 "[--downsample random|first|last|shuffled|nearest] [--view-bins N]\n");
    return 2;
  }
  auto reader = uf::OpenDataset(options.sequence);
  if (!reader.ok()) {
    std::fprintf(stderr, "bench_map_bias: %s\n", reader.error().c_str());
    return 1;
  }
  const uf::DatasetDescription& description = (*reader)->description();
  if (!description.ground_truth) {
    std::fprintf(stderr, "bench_map_bias: no ground truth in %s\n", options.sequence.c_str());
    return 1;
  }
  auto truth = uf::ReadTrajectory(description.ground_truth->string());
  if (!truth.ok() || !truth->has_stamps()) {
    std::fprintf(stderr, "bench_map_bias: ground truth: %s\n",
                 truth.ok() ? "no stamps" : truth.error().c_str());
    return 1;
  }
  uf::SE3 T_body_lidar;
  for (const uf::StreamInfo& stream : description.streams)
    if (stream.kind == uf::SensorKind::kLidar && stream.T_body_sensor) T_body_lidar = *stream.T_body_sensor;

  Maps maps(options);
  std::mt19937 engine(1);
  double part[kSurfaces][kBands] = {}, yaw_part[kSurfaces][kBands] = {}, residuals[kSurfaces][kBands] = {};
  double pull_sum = 0, pull_square_sum = 0, travelled = 0, yaw_sum = 0;
  int scans = 0, registered = 0;
  std::optional<Eigen::Vector3d> previous_centre;
  while (true) {
    auto next = (*reader)->Next();
    if (!next.ok()) {
      std::fprintf(stderr, "bench_map_bias: %s\n", next.error().c_str());
      return 1;
    }
    if (!*next) break;
    const auto* scan = std::get_if<uf::LidarScan>(&(*next)->data);
    if (scan == nullptr) continue;
    const auto middle = truth->PoseAt(scan->stamp + (scan->end - scan->stamp) / 2);
    if (!middle) continue;
    const Eigen::Vector3d centre = (*middle * T_body_lidar).translation();
    const double sweep_ns = static_cast<double>(scan->end - scan->stamp);
    const auto world_of = [&](const PreparedPoint& p) -> std::optional<Eigen::Vector3d> {
      const auto pose = truth->PoseAt(scan->stamp + static_cast<uf::Stamp>(p.alpha * sweep_ns));
      if (!pose) return std::nullopt;
      return *pose * (T_body_lidar * p.point_lidar);
    };
    const auto prepared = uf::estimator::PrepareScan(*scan, options.min_range_m, options.max_range_m);

    const Eigen::Vector3d step =
        previous_centre ? Eigen::Vector3d(centre - *previous_centre) : Eigen::Vector3d::Zero();
    if (step.norm() > 0.05) {  // moving: a direction of travel
      const Eigen::Vector3d forward = step.normalized();
      Matrix6d H = Matrix6d::Zero();
      std::array<Vector6d, kSurfaces * kBands> gradient;
      for (Vector6d& g : gradient) g.setZero();
      for (const PreparedPoint& p : Downsample(prepared, options.input_voxel_m, options.downsample, engine)) {
        const auto world = world_of(p);
        if (!world) continue;
        const auto plane = maps.PlaneNear(*world, centre);
        if (!plane) continue;
        const double r = plane->normal.dot(*world - plane->point);
        if (std::abs(r) > options.max_plane_distance_m) continue;
        const double w =
            std::min(1.0, options.huber_m / std::max(std::abs(r), 1e-12)) / (plane->sigma * plane->sigma);
        Vector6d J;
        J << plane->normal, (*world - centre).cross(plane->normal);
        H.noalias() += w * J * J.transpose();
        const int surface = SurfaceOf(plane->normal, forward), band = BandOf((*world - centre).norm());
        gradient[surface * kBands + band] += w * r * J;
        residuals[surface][band] += 1;
      }
      const Eigen::LDLT<Matrix6d> solver(H);
      if (solver.info() == Eigen::Success && H.trace() > 0) {
        double pull = 0, yaw = 0;
        for (int surface = 0; surface < kSurfaces; ++surface) {
          for (int band = 0; band < kBands; ++band) {
            const Vector6d step_part = -solver.solve(gradient[surface * kBands + band]);
            const double along = forward.dot(step_part.head<3>());
            part[surface][band] += along;
            yaw_part[surface][band] += step_part(5);
            pull += along;
            yaw += step_part(5);
          }
        }
        pull_sum += pull;
        yaw_sum += yaw;
        pull_square_sum += pull * pull;
        travelled += step.norm();
        ++registered;
      }
    }
    std::vector<Eigen::Vector3d> world_points;
    std::vector<int> rings;
    for (const PreparedPoint& p : Downsample(prepared, options.insert_voxel_m, options.downsample, engine)) {
      if (const auto world = world_of(p)) {
        world_points.push_back(*world);
        rings.push_back(p.ring);
      }
    }
    maps.Insert(world_points, rings, centre);
    previous_centre = centre;
    ++scans;
  }
  if (registered == 0) {
    std::fprintf(stderr, "bench_map_bias: no moving scan to register in %s\n", options.sequence.c_str());
    return 1;
  }
  const double mean = pull_sum / registered;
  const double spread = std::sqrt(std::max(0.0, pull_square_sum / registered - mean * mean));
  std::printf("bench_map_bias: %s, %d scans, %d registered from the truth over %.1f m\n",
              options.sequence.c_str(), scans, registered, travelled);
  std::printf("  along-track pull: %+.1f um per scan (scan to scan spread %.1f um), scale %+.1f ppm\n",
              1e6 * mean, 1e6 * spread, 1e6 * pull_sum / travelled);
  std::printf("  yaw pull: %+.2f urad per scan, %+.2f urad per m (about the world's z)\n",
              1e6 * yaw_sum / registered, 1e6 * yaw_sum / travelled);
  std::printf("  its parts in ppm (residuals), by the plane's surface and the point's range:\n");
  std::printf("    %-24s %22s %22s %22s\n", "", "< 10 m", "10-30 m", ">= 30 m");
  for (int surface = 0; surface < kSurfaces; ++surface) {
    std::printf("    %-24s", kSurfaceNames[surface]);
    for (int band = 0; band < kBands; ++band)
      std::printf(" %+9.1f (%10.0f)", 1e6 * part[surface][band] / travelled, residuals[surface][band]);
    std::printf("\n");
  }
  std::printf("  the yaw pull's parts in urad per m:\n");
  for (int surface = 0; surface < kSurfaces; ++surface) {
    std::printf("    %-24s", kSurfaceNames[surface]);
    for (int band = 0; band < kBands; ++band)
      std::printf(" %+22.2f", 1e6 * yaw_part[surface][band] / travelled);
    std::printf("\n");
  }
  return 0;
}
