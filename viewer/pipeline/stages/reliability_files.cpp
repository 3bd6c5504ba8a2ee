#include "viewer/pipeline/stages/reliability_files.h"

#include <algorithm>

#include "odometry/eval/series_plot.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {

namespace {

// Runs of consecutive keyframes that `in` (a value for the span's worst score, or none) puts inside,
// skipping those `scored` says nothing about.
template <typename In>
std::vector<DegenerateSpan> Spans(const std::vector<ScoredKeyframe>& scored, In in) {
  std::vector<DegenerateSpan> spans;
  bool open = false;
  for (const ScoredKeyframe& k : scored) {
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

const char* kHeader =
    "stamp_ns,modality,score,active,matches,translation_isotropy,rotation_isotropy,weak_x,weak_y,weak_z,"
    "speed_error_mps,yaw_rate_error_rad_s\n";

Status WritePlot(const std::filesystem::path& folder, const std::string& plot, const std::vector<double>& t,
                 const std::vector<double>& d, const std::string& name,
                 const std::optional<SeriesLevel>& level, const std::string& title) {
  return WriteSeriesPlot((folder / plot).string(), t, d, name, level, title,
                         "time since the first keyframe (s)", "D");
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

Expected<std::vector<std::string>> WriteReliabilityFiles(const std::filesystem::path& folder,
                                                         const std::vector<ScoredKeyframe>& scored) {
  std::string csv = kHeader;
  std::vector<double> lidar_t, lidar_d, wheel_t, wheel_d;
  for (const ScoredKeyframe& k : scored) {
    const double t = ToSeconds(k.stamp - scored.front().stamp);
    if (const std::optional<LidarDegeneracy>& d = k.lidar) {
      csv += std::to_string(k.stamp) + ",lidar," +
             PrintfText("%.4f,1,%.0f,%.5f,%.5f,%.4f,%.4f,%.4f,,\n", d->score, d->matches,
                        d->translation_isotropy, d->rotation_isotropy, d->weak_translation.x(),
                        d->weak_translation.y(), d->weak_translation.z());
      lidar_t.push_back(t);
      lidar_d.push_back(d->score);
    }
    if (const std::optional<WheelConsistency>& w = k.wheel) {
      csv += std::to_string(k.stamp) + ",wheel," +
             PrintfText("%.4f,%.0f,,,,,,,%.4f,%.4f\n", w->score, w->active ? 1.0 : 0.0, w->speed_error_mps,
                        w->yaw_rate_error_rad_s);
      wheel_t.push_back(t);
      wheel_d.push_back(w->score);
    }
  }
  if (Status s = WriteTextFileAtomically(folder / "reliability.csv", csv); !s.ok()) return s;
  std::vector<std::string> written = {"reliability.csv"};
  if (lidar_t.empty() && wheel_t.empty()) return written;
  std::error_code error;
  std::filesystem::create_directories(folder / "plots", error);
  if (error) return Status::Error((folder / "plots").string() + ": cannot create: " + error.message());
  if (!lidar_t.empty()) {
    const std::string plot = "plots/reliability_lidar.png";
    if (Status s = WritePlot(folder, plot, lidar_t, lidar_d, "LiDAR degeneracy D",
                             SeriesLevel{kDegenerateReported, "reported as degenerate from here"},
                             "LiDAR degeneracy per keyframe (0: every direction pinned, 1: one free)");
        !s.ok())
      return s;
    written.push_back(plot);
  }
  if (!wheel_t.empty()) {
    const std::string plot = "plots/reliability_wheel.png";
    if (Status s = WritePlot(folder, plot, wheel_t, wheel_d, "wheel D", std::nullopt,
                             "Wheel against the IMU per interval (0: agree; left out above the threshold)");
        !s.ok())
      return s;
    written.push_back(plot);
  }
  return written;
}

}  // namespace uf::pipeline
