// Scripted camera events at a true time t (darkness, exposure changes, a dark occluder close to the lens, a
// textured panel passing in front of the camera), reduced to what the renderer applies per frame: a gain on
// the linear radiance, the pixel noise, the occluder's transmission per image column and the panel's cover
// per column with its texture.
#pragma once

#include <vector>

#include "odometry/sim/sensors/camera_renderer.h"
#include "odometry/types/stamp.h"

namespace uf::sim {

inline constexpr double kDarknessIllumination = 0.1;  // illumination factor inside a darkness window
inline constexpr double kDarknessNoiseFactor = 3.0;   // noise factor inside a darkness window
inline constexpr float kOccluderRadiance = 0.02f;     // linear radiance of the (unlit) occluder, before gain
inline constexpr double kPanelTextureCellPx = 12.0;   // the passing panel's texture: value-noise cell, px

struct CameraConditions {
  double gain = 1.0;               // on linear radiance: exposure x exposure-change gains x illumination
  double illumination = 1.0;       // 1, or kDarknessIllumination inside a darkness window
  double noise_std_dn = 0.0;       // Gaussian noise in 8-bit DN
  bool occluded = false;           // inside an occlusion window
  double occluder_progress = 0.0;  // (t - begin) / (end - begin) of the first occlusion window holding t
  bool passing = false;            // inside a passing-panel window
  double passing_progress = 0.0;   // the same for the first passing-panel window holding t
};

CameraConditions ConditionsAt(const CameraConfig& config, Stamp t);

// Transmission in [0, 1] (0: fully covered by the occluder) of each image column at occluder progress s.
// The occluder is a vertical band of width W/3 with soft edges: with x' = x + 0.5 in [0, W] (x the pixel
// column coordinate) and d = |x' - c| - W/6 the signed distance outside the band edge,
//   transmission = smoothstep((d + b) / (2 b)),  smoothstep(a) = 3a^2 - 2a^3 on [0, 1], b = W/30,
// which is point-symmetric about the edge, so the covered area integrates to exactly W/3. The centre moves
// linearly c(s) = W/6 + b + s (W - W/3 - 2b), keeping the band and its soft edges inside the image.
// n sub-columns per pixel are averaged (the same box filter as the supersampled scene).
std::vector<float> OccluderTransmission(int width, int supersampling, double progress);

// A textured panel passing close in front of the camera (a vehicle crossing the view): a vertical band half
// the image wide whose left edge moves linearly from -W/2 (just outside the left border) at progress 0 to W
// (just past the right border) at progress 1, carrying its texture with it, so that the corners on it move
// with the panel and not with the scene (what a gate on the camera must keep out; docs/METHOD.md
// "Factor-wise reliability scheduling").
struct PassingPanel {
  std::vector<float> cover;  // per image column, the covered share in [0, 1] (n sub-columns averaged)
  double left_px = 0.0;      // the band's left edge in image x' = x + 0.5
};
PassingPanel PassingPanelAt(int width, int supersampling, double progress);
// The panel's linear radiance (before gain) at image x' (x + 0.5) and y' (y + 0.5): value noise in the
// panel's own coordinates (x' - left_px, y'), cell kPanelTextureCellPx, in [0.05, 0.65).
float PanelRadiance(const PassingPanel& panel, double x, double y);

}  // namespace uf::sim
