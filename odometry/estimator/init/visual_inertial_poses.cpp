#include "odometry/estimator/init/visual_inertial_poses.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>

#include "odometry/estimator/init/imu_chain.h"

namespace uf::estimator {
namespace {

// The baseline's direction rests on the tracks seen at both ends of the window: at least this many.
constexpr std::size_t kMinSpanningTracks = 8;
constexpr int kResectionRounds = 3;  // resection and triangulation in turn
// The rig's scale rests on at least this many spanning tracks with a depth from the rig.
constexpr std::size_t kMinRigDepths = 5;

// Step 1 (see the header): the camera centres c_0 = 0 .. c_last up to scale (|c_last| = 1), from the tracks
// seen at both ends of the window with enough parallax; `tracks` counts them.
struct Centres {
  std::vector<Eigen::Vector3d> c;
  int tracks = 0;
  std::string failure;
  std::vector<Eigen::Vector3d> points;  // the spanning tracks' points, in the same units
  std::vector<std::size_t> track_of;    // their indices in the tracks given
};

// A ray's weight in the linear fits below: (I - r r^T) / d^2, whose quadratic form is the squared miss of a
// point at distance d from the ray, divided by d^2 (an angle).
Eigen::Matrix3d AngularWeight(const Eigen::Vector3d& ray, double squared_distance) {
  return (Eigen::Matrix3d::Identity() - ray * ray.transpose()) / std::max(squared_distance, 1e-6);
}

// One observation of a track: its node and its unit ray in "lo".
struct NodeRay {
  std::size_t node = 0;
  Eigen::Vector3d ray;
};

// The point whose angular misses from the rays (from `centres`) are least, the distances taken at
// `previous` (linear).
Eigen::Vector3d ClosestPointToRays(const std::vector<NodeRay>& rays,
                                   const std::vector<Eigen::Vector3d>& centres,
                                   const Eigen::Vector3d& previous) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const NodeRay& r : rays) {
    const Eigen::Vector3d& centre = centres[r.node];
    const Eigen::Matrix3d M = AngularWeight(r.ray, (previous - centre).squaredNorm());
    H += M;
    b += M * centre;
  }
  return H.ldlt().solve(b);
}

Centres UpToScaleCentres(const std::vector<FeatureTrack>& tracks, const ImuChain& chain,
                         const SE3& T_body_camera, double min_parallax_rad) {
  const std::size_t last = chain.R.size() - 1;
  std::vector<std::vector<NodeRay>> spanning;  // the rays of the tracks seen at both ends, with parallax
  Centres centres;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const FeatureTrack& track = tracks[i];
    if (track.observations.front().first != 0 || track.observations.back().first != last) continue;
    std::vector<NodeRay> rays;
    for (const auto& [k, xy] : track.observations)
      rays.push_back({k, (chain.R[k] * (T_body_camera.so3() * xy.homogeneous())).normalized()});
    if (std::acos(std::clamp(rays.front().ray.dot(rays.back().ray), -1.0, 1.0)) < min_parallax_rad) continue;
    spanning.push_back(std::move(rays));
    centres.track_of.push_back(i);
  }
  centres.tracks = static_cast<int>(spanning.size());
  if (spanning.size() < kMinSpanningTracks) {
    centres.failure = std::to_string(spanning.size()) + " tracks span the window with parallax, need " +
                      std::to_string(kMinSpanningTracks);
    return centres;
  }
  // The baseline's direction: (r_0 x r_last)^T c_last = 0 for every such track.
  Eigen::MatrixXd A(spanning.size(), 3);
  for (std::size_t f = 0; f < spanning.size(); ++f)
    A.row(static_cast<long>(f)) =
        spanning[f].front().ray.cross(spanning[f].back().ray).normalized().transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  centres.c.assign(last + 1, Eigen::Vector3d::Zero());
  centres.c[last] = svd.matrixV().col(2);
  // Each track's point from its two end rays; the baseline's sign is the one that puts most in front.
  std::vector<Eigen::Vector3d> points(spanning.size());
  for (int attempt = 0; attempt < 2; ++attempt) {
    int in_front = 0;
    for (std::size_t f = 0; f < spanning.size(); ++f) {
      const NodeRay& first = spanning[f].front();
      const NodeRay& end = spanning[f].back();
      points[f] = ClosestPointToRays({first, end}, centres.c, Eigen::Vector3d::Zero());
      in_front += first.ray.dot(points[f]) > 0 && end.ray.dot(points[f] - centres.c[last]) > 0;
    }
    if (2 * in_front >= static_cast<int>(spanning.size())) break;
    centres.c[last] = -centres.c[last];
  }
  // Resection and triangulation in turn, with every observation: each node's centre whose rays miss the
  // points least (the rotation known: linear), then each point from all its rays; c_0 = 0 and |c_last| = 1
  // fix the gauge.
  for (int round = 0; round < kResectionRounds; ++round) {
    std::vector<Eigen::Matrix3d> H(last + 1, Eigen::Matrix3d::Zero());
    std::vector<Eigen::Vector3d> b(last + 1, Eigen::Vector3d::Zero());
    for (std::size_t f = 0; f < spanning.size(); ++f)
      for (const NodeRay& r : spanning[f]) {
        const Eigen::Matrix3d M = AngularWeight(r.ray, (points[f] - centres.c[r.node]).squaredNorm());
        H[r.node] += M;
        b[r.node] += M * points[f];
      }
    for (std::size_t k = 1; k <= last; ++k) centres.c[k] = H[k].ldlt().solve(b[k]);
    const double norm = centres.c[last].norm();
    for (Eigen::Vector3d& c : centres.c) c /= norm;
    for (std::size_t f = 0; f < spanning.size(); ++f)
      points[f] = ClosestPointToRays(spanning[f], centres.c, points[f] / norm);
  }
  for (std::size_t k = 1; k <= last; ++k)
    if (!centres.c[k].allFinite()) {
      centres.failure = "the camera centre of node " + std::to_string(k) + " is not determined";
      return centres;
    }
  centres.points = std::move(points);
  return centres;
}

// The stereo rig's scale (see the header): per spanning track with a depth d from the rig at node k, d
// over the point's depth in camera k of the structure, ((R_k R_bc)^T (P - c_k))_z; their median. None
// from fewer than kMinRigDepths tracks.
std::optional<double> RigScale(const std::vector<FeatureTrack>& tracks, const Centres& centres,
                               const ImuChain& chain, const SE3& T_body_camera) {
  std::vector<double> scales;
  for (std::size_t f = 0; f < centres.points.size(); ++f) {
    const FeatureTrack& track = tracks[centres.track_of[f]];
    for (const auto& [k, depth] : track.depths) {
      if (k >= centres.c.size() || !(depth > 0)) continue;
      const Eigen::Vector3d in_camera =
          (chain.R[k] * T_body_camera.so3()).inverse() * (centres.points[f] - centres.c[k]);
      if (in_camera.z() > 0) scales.push_back(depth / in_camera.z());
      break;  // one per track
    }
  }
  if (scales.size() < kMinRigDepths) return std::nullopt;
  std::nth_element(scales.begin(), scales.begin() + static_cast<long>(scales.size() / 2), scales.end());
  return scales[scales.size() / 2];
}

// Why the accelerometer cannot give the scale over the window (see the header), or nullopt.
std::optional<std::string> SteadyMotion(const ImuChain& chain, const VisualInertialStartConfig& config) {
  const std::size_t n = chain.R.size();
  double excursion = 0;
  for (std::size_t k = 0; k < n; ++k)
    excursion = std::max(excursion, (chain.b[k] - chain.t[k] / chain.t[n - 1] * chain.b[n - 1]).norm());
  if (excursion >= config.min_velocity_excursion_mps) return std::nullopt;
  std::ostringstream why;
  why << "the specific force departs from a constant one by " << excursion << " m/s over the window, need "
      << config.min_velocity_excursion_mps
      << " (at a steady velocity or acceleration the accelerometer does not see the scale)";
  return why.str();
}

}  // namespace

Expected<VisualInertialStart> VisualInertialPoses(std::span<const ImuPreintegration> preintegrations,
                                                  const std::vector<FeatureTrack>& tracks,
                                                  const SE3& T_body_camera,
                                                  const VisualInertialStartConfig& config) {
  ImuChain chain = ChainPreintegrations(preintegrations, Eigen::Vector3d::Zero());
  const std::size_t n = chain.R.size();
  if (n < 3) return Status::Error("visual-inertial start: need 3 nodes at least");
  std::vector<FeatureTrack> usable;
  for (const FeatureTrack& track : tracks) {
    bool inside = track.observations.size() >= 3;
    for (const auto& [k, xy] : track.observations) inside = inside && k < n && xy.allFinite();
    if (inside) usable.push_back(track);
  }
  if (static_cast<int>(usable.size()) < config.min_tracks)
    return Status::Error("visual-inertial start: " + std::to_string(usable.size()) +
                         " feature tracks over 3 nodes or more, need " + std::to_string(config.min_tracks));
  // Without a rig the accelerometer must see a changing motion (see the header).
  const bool rig =
      std::any_of(usable.begin(), usable.end(), [](const FeatureTrack& t) { return !t.depths.empty(); });
  if (!rig)
    if (std::optional<std::string> steady = SteadyMotion(chain, config))
      return Status::Error("visual-inertial start: " + *steady);
  Centres centres = UpToScaleCentres(usable, chain, T_body_camera, config.min_parallax_rad);
  if (!centres.failure.empty()) return Status::Error("visual-inertial start: " + centres.failure);
  // Step 2: the structure and the gyro bias together; the IMU chained again at that bias.
  std::vector<TrackObservations> spanning;
  for (const std::size_t i : centres.track_of) spanning.push_back(usable[i].observations);
  GyroBiasBundle bundle =
      AdjustWithGyroBias(preintegrations, spanning, T_body_camera, centres.c, std::move(centres.points));
  if (!bundle.gyro_bias.allFinite())
    return Status::Error("visual-inertial start: the bundle adjustment diverged");
  chain = ChainPreintegrations(preintegrations, bundle.gyro_bias);
  centres.c = std::move(bundle.centres);
  centres.points = std::move(bundle.points);
  // The rig's scale, 0 when there is none (an optional here trips GCC's maybe-uninitialized).
  const double rig_scale = rig ? RigScale(usable, centres, chain, T_body_camera).value_or(0.0) : 0.0;
  const bool scale_from_rig = rig_scale > 0;
  if (rig && !scale_from_rig)
    if (std::optional<std::string> steady = SteadyMotion(chain, config))
      return Status::Error("visual-inertial start: too few depths from the stereo rig, and " + *steady);
  // Step 3: the IMU's positions are p_k = s c_k - R_k t_bc + t_bc (p_0 = 0) and also
  // v_0 t_k + g t_k^2 / 2 + a_k: linear in y = [s, v_0, g], or in y = [v_0, g] with the rig's s.
  const Eigen::Vector3d& t_bc = T_body_camera.translation();
  const long v = scale_from_rig ? 0 : 1;  // where v_0 starts in y
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * (n - 1), v + 6);
  Eigen::VectorXd rhs(3 * (n - 1));
  for (std::size_t k = 1; k < n; ++k) {
    const long r = 3 * static_cast<long>(k - 1);
    rhs.segment<3>(r) = chain.a[k] + (chain.R[k] * t_bc) - t_bc;
    if (scale_from_rig)
      rhs.segment<3>(r) -= rig_scale * centres.c[k];
    else
      A.block<3, 1>(r, 0) = centres.c[k];
    A.block<3, 3>(r, v) = -chain.t[k] * Eigen::Matrix3d::Identity();
    A.block<3, 3>(r, v + 3) = -0.5 * chain.t[k] * chain.t[k] * Eigen::Matrix3d::Identity();
  }
  const Eigen::MatrixXd normal = A.transpose() * A;
  const Eigen::VectorXd y = normal.ldlt().solve(A.transpose() * rhs);
  if (!y.allFinite()) return Status::Error("visual-inertial start: singular alignment");
  VisualInertialStart start;
  start.scale = scale_from_rig ? rig_scale : y(0);
  start.scale_from_rig = scale_from_rig;
  if (!(start.scale > 0))
    return Status::Error("visual-inertial start: the scale comes out " + std::to_string(start.scale) +
                         " (the IMU does not fit the camera's motion)");
  start.velocity = y.segment<3>(v);
  start.gravity = y.segment<3>(v + 3);
  start.tracks = centres.tracks;
  start.gyro_bias = bundle.gyro_bias;
  start.reprojection_rms = bundle.reprojection_rms;
  // The covariance of y from the fit's own residual (its variance per row).
  const long dof = A.rows() - A.cols();
  const double variance = dof > 0 ? (A * y - rhs).squaredNorm() / static_cast<double>(dof) : INFINITY;
  const Eigen::MatrixXd covariance =
      variance * normal.ldlt().solve(Eigen::MatrixXd::Identity(A.cols(), A.cols()));
  const double g_norm = start.gravity.norm();
  const Eigen::Vector3d g_unit = start.gravity / g_norm;
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - g_unit * g_unit.transpose();
  const auto largest = [](const Eigen::Matrix3d& covariance) {
    return std::sqrt(
        std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues()(2)));
  };
  start.tilt_sigma_rad = largest(across * covariance.block<3, 3>(v + 3, v + 3) * across) / g_norm;
  start.velocity_sigma_mps = largest(covariance.block<3, 3>(v, v));
  std::ostringstream why;
  if (!std::isfinite(g_norm) || std::abs(g_norm - config.gravity) > config.max_gravity_error * config.gravity)
    why << "gravity " << g_norm << " m/s^2 is not within " << 100 * config.max_gravity_error << " % of "
        << config.gravity;
  else if (!(start.tilt_sigma_rad <= config.max_tilt_sigma_rad))
    why << "gravity's direction known to " << start.tilt_sigma_rad * 180 / std::numbers::pi << " deg, need "
        << config.max_tilt_sigma_rad * 180 / std::numbers::pi;
  else if (!(start.velocity_sigma_mps <= config.max_velocity_sigma_mps))
    why << "the velocity known to " << start.velocity_sigma_mps << " m/s, need "
        << config.max_velocity_sigma_mps;
  if (!why.str().empty()) return Status::Error("visual-inertial start: " + why.str());
  for (std::size_t k = 0; k < n; ++k) {
    const double t = chain.t[k];
    start.poses.emplace_back(chain.R[k], t * start.velocity + 0.5 * t * t * start.gravity + chain.a[k]);
  }
  return start;
}

}  // namespace uf::estimator
