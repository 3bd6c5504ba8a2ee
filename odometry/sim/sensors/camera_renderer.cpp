#include "odometry/sim/sensors/camera_renderer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "odometry/sim/scene/scene.h"
#include "odometry/sim/sensors/camera_events.h"
#include "odometry/sim/sensors/camera_pixel_encoding.h"
#include "odometry/sim/sensors/parallel_for.h"

namespace uf::sim {
namespace {

constexpr std::size_t kMaxBearingTable = 1 << 22;  // sub-samples whose bearings are cached (48 MB)
constexpr double kRoundTripTolerancePx = 1e-3;     // distortion fold-over check

// SplitMix64's finaliser: a bijective 64-bit mix, used to derive independent sub-seeds.
std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Radiance (linear RGB) of the sky in unit world direction d, by elevation e = d.z: from the horizon colour
// to the zenith colour as sqrt(e) above the horizon; below it, a ground haze reached 0.1 rad under it.
Eigen::Vector3f SkyRadiance(const Eigen::Vector3f& d) {
  const Eigen::Vector3f horizon(0.78f, 0.83f, 0.88f), zenith(0.28f, 0.45f, 0.80f),
      ground(0.32f, 0.30f, 0.27f);
  const float e = d.z();
  if (e >= 0.0f) return horizon + (zenith - horizon) * std::sqrt(std::min(e, 1.0f));
  return horizon + (ground - horizon) * std::min(1.0f, -10.0f * e);
}

}  // namespace

CameraRenderer::CameraRenderer(const CameraConfig& config, const RayCaster& caster,
                               const TrajectorySpline& trajectory, const SE3& T_body_camera,
                               std::uint64_t seed)
    : config_(config),
      model_(CameraModelOf(config)),
      caster_(&caster),
      trajectory_(&trajectory),
      T_body_camera_(T_body_camera),
      seed_(seed),
      sun_world_(config.sun_direction_world.normalized().cast<float>()) {}

Expected<CameraRenderer> CameraRenderer::Create(const CameraConfig& config, const RayCaster& caster,
                                                const TrajectorySpline& trajectory, const SE3& T_body_camera,
                                                std::uint64_t seed) {
  if (Status status = ValidateCameraConfig(config); !status.ok()) return status;
  if (!T_body_camera.matrix().allFinite()) return Status::Error("camera T_body_camera: not finite");
  CameraRenderer renderer(config, caster, trajectory, T_body_camera, seed);

  // The distortion must be one-to-one over the image: every border sub-sample's bearing projects back onto
  // it (Project refuses points beyond the fold radius). Inside, the radial profile is then increasing too.
  const int n = config.supersampling;
  const int sub_width = n * config.pinhole.width, sub_height = n * config.pinhole.height;
  const auto sub_pixel = [n](int k) { return (k + 0.5) / n - 0.5; };
  const auto round_trips = [&](int kx, int ky) {
    const Eigen::Vector2d pixel(sub_pixel(kx), sub_pixel(ky));
    const auto back = renderer.model_.Project(renderer.model_.Unproject(pixel));
    return back && (*back - pixel).norm() < kRoundTripTolerancePx;
  };
  for (int k = 0; k < std::max(sub_width, sub_height); ++k) {
    const int kx = std::min(k, sub_width - 1), ky = std::min(k, sub_height - 1);
    for (const auto& [x, y] :
         {std::pair{kx, 0}, std::pair{kx, sub_height - 1}, std::pair{0, ky}, std::pair{sub_width - 1, ky}}) {
      if (round_trips(x, y)) continue;
      std::ostringstream message;
      message << "camera distortion (k1 " << config.k1 << ", k2 " << config.k2 << ", p1 " << config.p1
              << ", p2 " << config.p2 << ", k3 " << config.k3 << "): folds over inside the image, pixel ("
              << sub_pixel(x) << ", " << sub_pixel(y) << ") does not project back onto itself";
      return Status::Error(message.str());
    }
  }

  const auto table_size = static_cast<std::size_t>(sub_width) * static_cast<std::size_t>(sub_height);
  if (table_size <= kMaxBearingTable) {
    renderer.bearings_.resize(table_size);
    ParallelFor(static_cast<std::size_t>(sub_height), config.threads,
                [&](std::size_t begin, std::size_t end) {
                  for (std::size_t r = begin; r < end; ++r) {
                    renderer.SubRowBearings(static_cast<int>(r),
                                            &renderer.bearings_[r * static_cast<std::size_t>(sub_width)]);
                  }
                });
  }
  return renderer;
}

void CameraRenderer::SubRowBearings(int sub_row, Eigen::Vector3f* out) const {
  // Sub-sample k of a sub-row sits at pixel coordinate (k + 0.5) / n - 0.5 (pixel centres are integers).
  const int n = config_.supersampling;
  const double y = (sub_row + 0.5) / n - 0.5;
  for (int k = 0; k < n * config_.pinhole.width; ++k) {
    out[k] = model_.Unproject(Eigen::Vector2d((k + 0.5) / n - 0.5, y)).cast<float>();
  }
}

void CameraRenderer::FillRowRays(const SE3& T_world_camera, int row, std::vector<Eigen::Vector3f>& scratch,
                                 std::vector<Ray>& rays) const {
  const int n = config_.supersampling;
  const std::size_t sub_width = static_cast<std::size_t>(n) * static_cast<std::size_t>(config_.pinhole.width);
  const Eigen::Matrix3f R_world_camera = T_world_camera.rotation().cast<float>();
  const Eigen::Vector3f origin = T_world_camera.translation().cast<float>();
  rays.resize(sub_width * static_cast<std::size_t>(n));
  scratch.resize(sub_width);
  for (int sy = 0; sy < n; ++sy) {
    const int sub_row = row * n + sy;
    const Eigen::Vector3f* bearings = scratch.data();
    if (bearings_.empty()) {
      SubRowBearings(sub_row, scratch.data());
    } else {
      bearings = &bearings_[static_cast<std::size_t>(sub_row) * sub_width];
    }
    Ray* out = &rays[static_cast<std::size_t>(sy) * sub_width];
    for (std::size_t k = 0; k < sub_width; ++k) {
      out[k].origin = origin;
      out[k].direction = R_world_camera * bearings[k];  // d_world = R_world_camera d_camera
      out[k].max_range = std::numeric_limits<float>::infinity();
    }
  }
}

Status CameraRenderer::CheckTime(Stamp t) const {
  if (trajectory_->Contains(t)) return Status();
  return Status::Error("camera render time " + FormatSeconds(t) + " s: outside the trajectory [" +
                       FormatSeconds(trajectory_->begin()) + ", " + FormatSeconds(trajectory_->end()) +
                       "] s");
}

SE3 CameraRenderer::CameraPose(Stamp t) const {
  assert(trajectory_->Contains(t));
  return trajectory_->Evaluate(t).T_world_body * T_body_camera_;
}

Expected<std::vector<Ray>> CameraRenderer::RowRays(Stamp t, int row) const {
  assert(row >= 0 && row < config_.pinhole.height);
  if (Status status = CheckTime(t); !status.ok()) return status;
  std::vector<Eigen::Vector3f> scratch;
  std::vector<Ray> rays;
  FillRowRays(CameraPose(t), row, scratch, rays);
  return rays;
}

Expected<CameraFrame> CameraRenderer::Render(Stamp t, int camera_index) const {
  if (Status status = CheckTime(t); !status.ok()) return status;
  const SE3 T_world_camera = CameraPose(t);
  const CameraConditions conditions = ConditionsAt(config_, t);
  const int width = config_.pinhole.width, n = config_.supersampling;
  const std::vector<float> occluder = conditions.occluded
                                          ? OccluderTransmission(width, n, conditions.occluder_progress)
                                          : std::vector<float>();
  const PassingPanel panel =
      conditions.passing ? PassingPanelAt(width, n, conditions.passing_progress) : PassingPanel();

  CameraFrame frame;
  frame.stamp = t;
  frame.camera = camera_index;
  Image& image = frame.image;
  image.width = width;
  image.height = config_.pinhole.height;
  image.channels = 3;
  image.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(config_.pinhole.height) * 3);

  const auto ambient = static_cast<float>(config_.ambient);
  const float gain = static_cast<float>(conditions.gain) / static_cast<float>(n * n);  // and the box filter
  const auto noise_std = static_cast<float>(conditions.noise_std_dn);
  const float* srgb_table = SrgbDnTable();
  const float* normal_table = StandardNormalTable();
  const std::uint64_t frame_seed = SplitMix64(SplitMix64(seed_) ^ static_cast<std::uint64_t>(t));

  ParallelFor(
      static_cast<std::size_t>(config_.pinhole.height), config_.threads,
      [&](std::size_t begin, std::size_t end) {
        std::vector<Eigen::Vector3f> scratch, radiance(static_cast<std::size_t>(width));
        std::vector<Ray> rays;
        std::vector<RayHit> hits;
        for (std::size_t row = begin; row < end; ++row) {
          FillRowRays(T_world_camera, static_cast<int>(row), scratch, rays);
          hits.resize(rays.size());
          caster_->Cast(rays, hits);

          // Radiance summed over the n x n sub-samples of each pixel. Lambert under the sun plus ambient:
          // L = colour (ambient + (1 - ambient) max(0, n . l)), n the normal facing the camera, l to the sun.
          std::fill(radiance.begin(), radiance.end(), Eigen::Vector3f::Zero());
          std::size_t i = 0;  // ray index, in the order of RowRays
          for (int sy = 0; sy < n; ++sy) {
            for (Eigen::Vector3f& sum : radiance) {
              for (int sx = 0; sx < n; ++sx, ++i) {
                const Ray& ray = rays[i];
                const RayHit& hit = hits[i];
                if (!hit.hit()) {
                  sum += SkyRadiance(ray.direction);
                  continue;
                }
                const float lambert = ambient + (1.0f - ambient) * std::max(0.0f, hit.normal.dot(sun_world_));
                if (!config_.textured) {
                  sum += AppearanceOf(hit.material).base_rgb * lambert;
                  continue;
                }
                const Eigen::Vector3d point = ray.origin.cast<double>() + static_cast<double>(hit.distance) *
                                                                              ray.direction.cast<double>();
                sum += SurfaceColor(hit.material, point, hit.normal) * lambert;
              }
            }
          }

          // Passing panel, occluder, gain, sRGB encoding, noise in DN (the same draws for every content: one
          // 64-bit output gives four 16-bit normal samples), rounding to 8 bits.
          std::mt19937_64 rng(SplitMix64(frame_seed ^ SplitMix64(row)));
          std::uint64_t bits = 0;
          int bits_left = 0;
          std::uint8_t* out = &image.pixels[row * static_cast<std::size_t>(width) * 3];
          for (int u = 0; u < width; ++u) {
            Eigen::Vector3f linear = radiance[static_cast<std::size_t>(u)] * gain;
            if (!panel.cover.empty() && panel.cover[static_cast<std::size_t>(u)] > 0.0f) {
              const float cover = panel.cover[static_cast<std::size_t>(u)];
              const float panel_radiance = PanelRadiance(panel, u + 0.5, static_cast<double>(row) + 0.5) *
                                           static_cast<float>(conditions.gain);
              linear = linear * (1.0f - cover) + Eigen::Vector3f::Constant(cover * panel_radiance);
            }
            if (!occluder.empty()) {
              const float transmission = occluder[static_cast<std::size_t>(u)];
              linear = linear * transmission +
                       Eigen::Vector3f::Constant((1.0f - transmission) * kOccluderRadiance *
                                                 static_cast<float>(conditions.gain));
            }
            for (int c = 0; c < 3; ++c) {
              float dn = LinearToSrgbDn(srgb_table, linear[c]);
              if (noise_std > 0.0f) {
                if (bits_left == 0) bits = rng(), bits_left = 4;
                dn += noise_std *
                      StandardNormalFromBits(normal_table, static_cast<std::uint16_t>(bits & 0xFFFFu));
                bits >>= 16;
                --bits_left;
              }
              out[3 * u + c] = static_cast<std::uint8_t>(std::clamp(dn, 0.0f, 255.0f) + 0.5f);
            }
          }
        }
      });
  return frame;
}

}  // namespace uf::sim
