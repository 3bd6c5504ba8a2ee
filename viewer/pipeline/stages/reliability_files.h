// The reliability scores of a run (docs/METHOD.md "Factor-wise reliability scheduling"): reliability.csv,
// one row per keyframe and modality with the score D, the inputs it came from (blank where they belong to
// another modality) and whether the modality's factors were active, and plots/reliability_<modality>.png
// (D over time). Scored: the LiDAR (its rows are always active: the LiDAR is not switched off, only its weak
// directions with lo.drop_weak_directions), with wheel scheduling the wheel, and each GNSS fix the
// innovation test saw (a row at the fix's stamp; active: its factor joined the window), and with an IMU its
// interval ending at the keyframe (always active: clipped readings loosen its factor, none leaves it out),
// and with the camera each frame the window checked (a row at its node's stamp; active: its observations
// joined the window).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "odometry/types/keyframe.h"
#include "odometry/types/status.h"

namespace uf::pipeline {

// The LiDAR degeneracy the report lists as spans, and the plot marks: D >= 0.5 (the weakest direction with
// under half the information of the healthy isotropy, lidar_degeneracy.h).
constexpr double kDegenerateReported = 0.5;

struct ScoredKeyframe {
  Stamp stamp = 0;
  std::optional<LidarDegeneracy> lidar;
  std::optional<WheelConsistency> wheel;
  std::vector<GnssCheck> gnss;  // the fixes checked since the previous keyframe
  std::optional<ImuReliability> imu;
  std::vector<CameraCheck> camera;  // the frames checked since the previous keyframe
};

// Where the LiDAR was degenerate (D >= threshold) as time intervals, for the report: [first, last] stamps
// of each run of consecutive LiDAR-scored keyframes at or above it.
struct DegenerateSpan {
  Stamp first = 0, last = 0;
  int keyframes = 0;
  double worst = 0;  // the highest D in it
};
std::vector<DegenerateSpan> DegenerateSpans(const std::vector<ScoredKeyframe>& scored, double threshold);
// Where the wheel's factors were left out (inactive), likewise, with the highest score in each span.
std::vector<DegenerateSpan> SuppressedWheelSpans(const std::vector<ScoredKeyframe>& scored);
// Where the camera's frames were left out (inactive), likewise, at the frames' stamps.
std::vector<DegenerateSpan> SuppressedCameraSpans(const std::vector<ScoredKeyframe>& scored);
// Where the IMU clipped (an interval with a reading at its full scale), likewise.
std::vector<DegenerateSpan> ClippedImuSpans(const std::vector<ScoredKeyframe>& scored);

// What WriteReliabilityFiles wrote, relative to its folder: every file, and each modality's plot (empty
// where nothing was scored for it).
struct ReliabilityFiles {
  std::vector<std::string> files;
  std::string lidar_plot, wheel_plot, gnss_plot, imu_plot, camera_plot;
};

// Writes folder/reliability.csv and folder/plots/reliability_lidar.png, reliability_wheel.png,
// reliability_gnss.png, reliability_imu.png and reliability_camera.png (each plot only with a keyframe scored
// for it). Errors: a file that cannot be written (nothing half written is left behind).
Expected<ReliabilityFiles> WriteReliabilityFiles(const std::filesystem::path& folder,
                                                 const std::vector<ScoredKeyframe>& scored);

}  // namespace uf::pipeline
