// The simulated pinhole camera: renders a Scene through the RayCaster as an 8-bit sRGB image at a true time
// t (global shutter, mid-exposure), with exact radial-tangential distortion, Lambert shading under a sun,
// a sky for rays that miss, supersampling, Gaussian pixel noise and scripted events (darkness, exposure
// changes, a dark occluder sliding across the lens, a textured panel passing in front of the camera).
//
// Frames: camera axes are OpenCV's (x right, y down, z forward); T_world_camera(t) = T_world_body(t) *
// T_body_camera with T_world_body(t) from the TrajectorySpline. World z is up.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/time_window.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"
#include "odometry/types/pinhole_intrinsics.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::sim {

struct CameraConfig {
  // Pixels: width and height in [1, 16384], (cx, cy) inside the image.
  PinholeIntrinsics pinhole = {.width = 640, .height = 480, .fx = 400, .fy = 400, .cx = 319.5, .cy = 239.5};
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;  // radial-tangential distortion (rendered exactly)
  double rate_hz = 10.0;                          // frames per second, in (0, 1000]
  double noise_std_dn = 1.0;  // Gaussian pixel noise, 8-bit digital numbers (after sRGB encoding), >= 0
  int supersampling = 1;      // n x n rays per pixel (box-filter anti-aliasing), in [1, 16]
  Eigen::Vector3d sun_direction_world = {0.4, 0.3, 0.85};  // towards the sun, normalised by the renderer
  double ambient = 0.35;  // Lambert: colour * (ambient + (1-ambient) max(0, n.l)), in [0, 1]
  double exposure = 1.0;  // brightness gain on the linear colour, > 0
  bool textured = true;   // false: each material's plain base colour (AppearanceOf), e.g. calibration targets
  std::vector<TimeWindow> darkness;  // illumination x 0.1 and noise x 3 inside (night / unlit tunnel)
  std::vector<std::pair<TimeWindow, double>> exposure_changes;  // gain multiplier (> 0) inside the window
  // A dark blurry occluder close to the lens (wiper, hand): a vertical band 1/3 of the image wide with soft
  // edges, sliding from the left to the right side of the image over the window.
  std::vector<TimeWindow> occlusions;
  // A textured panel passing close in front of the camera (a vehicle crossing the view): a band half the
  // image wide entering at the left border and leaving at the right over the window, its texture moving
  // with it (camera_events.h).
  std::vector<TimeWindow> passing_panels;
  int threads = 0;  // render threads; 0: hardware concurrency. The output does not depend on it.
};

// The first bad field, e.g. "camera.fx: must be positive and finite, got 0"; ok otherwise.
Status ValidateCameraConfig(const CameraConfig& config);

// The intrinsics as the project's camera model (config assumed valid).
PinholeRadtan CameraModelOf(const CameraConfig& config);

class CameraRenderer {
 public:
  // Keeps references to `caster` and `trajectory`: both must outlive the renderer. Fails for an invalid
  // config, a non-finite T_body_camera, or a distortion that folds over inside the image (a pixel whose
  // bearing does not project back onto it).
  static Expected<CameraRenderer> Create(const CameraConfig& config, const RayCaster& caster,
                                         const TrajectorySpline& trajectory, const SE3& T_body_camera,
                                         std::uint64_t seed);

  // Global shutter at true time t (mid-exposure). Returns a CameraFrame with `image` filled (8-bit RGB,
  // channels = 3, sRGB-encoded from the linear colour) and `encoded` empty; frame.stamp = t. Deterministic
  // in (seed, t) whatever the thread count. Fails when t is outside the trajectory.
  Expected<CameraFrame> Render(Stamp t, int camera_index = 0) const;

  // The rays Render casts for image row `row` at time t (world frame), in the order it casts them:
  // sub-row sy in [0, n), then column u in [0, width), then sub-column sx in [0, n), with n = supersampling;
  // ray (sy, u, sx) passes through pixel (u - 0.5 + (sx + 0.5) / n, row - 0.5 + (sy + 0.5) / n).
  // Fails when t is outside the trajectory.
  Expected<std::vector<Ray>> RowRays(Stamp t, int row) const;

  // T_world_camera(t) = T_world_body(t) * T_body_camera; asserts that t is inside the trajectory.
  SE3 CameraPose(Stamp t) const;

  const CameraConfig& config() const { return config_; }
  const PinholeRadtan& model() const { return model_; }

 private:
  CameraRenderer(const CameraConfig& config, const RayCaster& caster, const TrajectorySpline& trajectory,
                 const SE3& T_body_camera, std::uint64_t seed);

  // Camera-frame unit bearings of sub-row `sub_row` (in [0, n * height)), n * width of them.
  void SubRowBearings(int sub_row, Eigen::Vector3f* out) const;
  // Fills `rays` (n * n * width) for `row` from the pose, as documented at RowRays.
  void FillRowRays(const SE3& T_world_camera, int row, std::vector<Eigen::Vector3f>& scratch,
                   std::vector<Ray>& rays) const;
  Status CheckTime(Stamp t) const;

  CameraConfig config_;
  PinholeRadtan model_;
  const RayCaster* caster_;
  const TrajectorySpline* trajectory_;
  SE3 T_body_camera_;
  std::uint64_t seed_;
  Eigen::Vector3f sun_world_;  // unit, towards the sun
  // Bearings of every sub-sample (n * height rows of n * width), or empty when that table would be too big
  // (then they are computed per row).
  std::vector<Eigen::Vector3f> bearings_;
};

}  // namespace uf::sim
