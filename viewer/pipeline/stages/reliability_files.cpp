#include "viewer/pipeline/stages/reliability_files.h"

#include <algorithm>
#include <utility>

#include "odometry/eval/series_plot.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {

namespace {

// Runs of consecutive items (keyframes, or camera frames: anything with a stamp) that `in` (a value for the
// span's worst score, or none) puts inside, skipping those `in` says nothing about.
template <typename Item, typename In>
std::vector<DegenerateSpan> Spans(const std::vector<Item>& items, In in) {
  std::vector<DegenerateSpan> spans;
  bool open = false;
  for (const Item& k : items) {
    const std::optional<std::optional<double>> inside = in(k);
    if (!inside) continue;  // not scored for this modality
    if (!*inside) {
      open = false;
      continue;
    }
    if (!open) spans.push_back({k.stamp, k.stamp, 0, 0.0});
    open = true;
    DegenerateSpan& span = spans.back();
    span.last = k.stamp;
    ++span.keyframes;
    span.worst = std::max(span.worst, **inside);
  }
  return spans;
}

// The columns: each modality's own, blank on the other modalities' rows.
const char* kHeader =
    "stamp_ns,modality,score,active,"
    "matches,translation_isotropy,rotation_isotropy,weak_x,weak_y,weak_z,"  // lidar
    "speed_error_mps,speed_change_error_mps,yaw_rate_error_rad_s,"          // wheel
    "fix_quality,covariance_trace_m2,innovation_d2,"                        // gnss
    "excitation,preintegration_chi2,clipped_steps,"                         // imu
    "tracks_checked,tracks_agreeing,grid_occupancy,motion_error_px\n";      // camera

// The modalities' blocks of columns in the header's order, and how many columns each has.
enum Block { kLidarBlock, kWheelBlock, kGnssBlock, kImuBlock, kCameraBlock, kBlocks };
constexpr int kBlockColumns[kBlocks] = {6, 3, 3, 3, 4};

// One modality's D over time, for its plot.
struct Series {
  Series(std::string plot_, std::string name_, std::string title_, std::optional<SeriesLevel> level_ = {})
      : plot(std::move(plot_)), name(std::move(name_)), title(std::move(title_)), level(std::move(level_)) {}
  std::string plot, name, title;
  std::optional<SeriesLevel> level;
  std::vector<double> t, d;
};

// One row of reliability.csv: the common columns, then `own` (the block's values, comma-separated) in its
// block's place and blanks in the others'.
std::string Row(Stamp stamp, const char* modality, double score, bool active, Block block,
                const std::string& own) {
  std::string row =
      std::to_string(stamp) + "," + modality + PrintfText(",%.4f,%.0f", score, active ? 1.0 : 0.0);
  for (int b = 0; b < kBlocks; ++b) row += b == block ? "," + own : std::string(kBlockColumns[b], ',');
  return row + "\n";
}

}  // namespace

std::vector<DegenerateSpan> DegenerateSpans(const std::vector<ScoredKeyframe>& scored, double threshold) {
  return Spans(scored, [threshold](const ScoredKeyframe& k) -> std::optional<std::optional<double>> {
    if (!k.lidar) return std::nullopt;
    return k.lidar->score >= threshold ? std::optional<double>(k.lidar->score) : std::nullopt;
  });
}

std::vector<DegenerateSpan> SuppressedWheelSpans(const std::vector<ScoredKeyframe>& scored) {
  return Spans(scored, [](const ScoredKeyframe& k) -> std::optional<std::optional<double>> {
    if (!k.wheel) return std::nullopt;
    return k.wheel->active ? std::nullopt : std::optional<double>(k.wheel->score);
  });
}

// A span per run of consecutive left-out frames (the frames are the unit here, not the keyframes).
std::vector<DegenerateSpan> SuppressedCameraSpans(const std::vector<ScoredKeyframe>& scored) {
  std::vector<CameraCheck> frames;
  for (const ScoredKeyframe& k : scored) frames.insert(frames.end(), k.camera.begin(), k.camera.end());
  return Spans(frames, [](const CameraCheck& c) -> std::optional<std::optional<double>> {
    return c.active ? std::nullopt : std::optional<double>(c.score);
  });
}

std::vector<DegenerateSpan> ClippedImuSpans(const std::vector<ScoredKeyframe>& scored) {
  return Spans(scored, [](const ScoredKeyframe& k) -> std::optional<std::optional<double>> {
    if (!k.imu) return std::nullopt;
    return k.imu->clipped_steps > 0 ? std::optional<double>(k.imu->score) : std::nullopt;
  });
}

Expected<ReliabilityFiles> WriteReliabilityFiles(const std::filesystem::path& folder,
                                                 const std::vector<ScoredKeyframe>& scored) {
  std::string csv = kHeader;
  Series lidar{"plots/reliability_lidar.png", "LiDAR degeneracy D",
               "LiDAR degeneracy per keyframe (0: every direction pinned, 1: one free)",
               SeriesLevel{kDegenerateReported, "reported as degenerate from here"}};
  Series wheel{"plots/reliability_wheel.png", "wheel D",
               "Wheel against the IMU per interval (0: agree; left out above the threshold)"};
  Series gnss{"plots/reliability_gnss.png", "GNSS D",
              "GNSS fixes (0: RTK fixed, as predicted; 1: no quality, far off the prediction)"};
  Series imu{"plots/reliability_imu.png", "IMU D",
             "IMU per interval (excitation, preintegration residual, clipped readings; 1: none reliable)"};
  Series camera{"plots/reliability_camera.png", "camera D",
                "Camera frames against the predicted motion (0: agree; with the gate on, left out above its "
                "threshold)",
                SeriesLevel{0.5, "the gate's default threshold (visual.schedule.threshold)"}};
  // A row in the CSV and a point in its modality's plot.
  const auto add = [&](Series& series, Stamp stamp, const char* modality, double score, bool active,
                       Block block, const std::string& own) {
    csv += Row(stamp, modality, score, active, block, own);
    series.t.push_back(ToSeconds(stamp - scored.front().stamp));
    series.d.push_back(score);
  };
  for (const ScoredKeyframe& k : scored) {
    if (const std::optional<LidarDegeneracy>& d = k.lidar)
      add(lidar, k.stamp, "lidar", d->score, true, kLidarBlock,
          PrintfText("%.0f,%.5f,%.5f,%.4f,%.4f,%.4f", d->matches, d->translation_isotropy,
                     d->rotation_isotropy, d->weak_translation.x(), d->weak_translation.y(),
                     d->weak_translation.z()));
    if (const std::optional<WheelConsistency>& w = k.wheel)
      add(wheel, k.stamp, "wheel", w->score, w->active, kWheelBlock,
          PrintfText("%.4f,%.4f,%.4f", w->speed_error_mps, w->speed_change_error_mps,
                     w->yaw_rate_error_rad_s));
    for (const GnssCheck& g : k.gnss)
      add(gnss, g.stamp, "gnss", g.score, g.active, kGnssBlock,
          PrintfText("%.2f,%.4f,%.3f", g.fix_quality, g.covariance_trace_m2, g.innovation_d2));
    if (const std::optional<ImuReliability>& m = k.imu)
      add(imu, k.stamp, "imu", m->score, true, kImuBlock,
          PrintfText("%.4f,%.3f,%.0f", m->excitation, m->preintegration_chi2, m->clipped_steps));
    for (const CameraCheck& c : k.camera)
      add(camera, c.stamp, "camera", c.score, c.active, kCameraBlock,
          PrintfText("%.0f,%.0f,%.4f,%.3f", c.tracks_checked, c.tracks_agreeing, c.grid_occupancy,
                     c.motion_error_px));
  }
  if (Status s = WriteTextFileAtomically(folder / "reliability.csv", csv); !s.ok()) return s;
  ReliabilityFiles written;
  written.files = {"reliability.csv"};
  if (scored.empty()) return written;
  std::error_code error;
  std::filesystem::create_directories(folder / "plots", error);
  if (error) return Status::Error((folder / "plots").string() + ": cannot create: " + error.message());
  const std::pair<const Series*, std::string*> plots[] = {{&lidar, &written.lidar_plot},
                                                          {&wheel, &written.wheel_plot},
                                                          {&gnss, &written.gnss_plot},
                                                          {&imu, &written.imu_plot},
                                                          {&camera, &written.camera_plot}};
  for (const auto& [series, plot] : plots) {
    if (series->t.empty()) continue;
    if (Status s = WriteSeriesPlot((folder / series->plot).string(), series->t, series->d, series->name,
                                   series->level, series->title, "time since the first keyframe (s)", "D");
        !s.ok())
      return s;
    written.files.push_back(series->plot);
    *plot = series->plot;
  }
  return written;
}

}  // namespace uf::pipeline
