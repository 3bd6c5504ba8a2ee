#include "viewer/pipeline/stages/reliability_files.h"

#include <algorithm>

#include "odometry/eval/series_plot.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {

std::vector<DegenerateSpan> DegenerateSpans(const std::vector<ScoredKeyframe>& scored, double threshold) {
  std::vector<DegenerateSpan> spans;
  bool open = false;
  for (const ScoredKeyframe& k : scored) {
    if (k.lidar.score < threshold) {
      open = false;
      continue;
    }
    if (!open) spans.push_back({k.stamp, k.stamp, 0, 0.0});
    open = true;
    DegenerateSpan& span = spans.back();
    span.last = k.stamp;
    ++span.keyframes;
    span.worst = std::max(span.worst, k.lidar.score);
  }
  return spans;
}

Expected<std::vector<std::string>> WriteReliabilityFiles(const std::filesystem::path& folder,
                                                         const std::vector<ScoredKeyframe>& scored) {
  std::string csv =
      "stamp_ns,modality,score,active,matches,translation_isotropy,rotation_isotropy,weak_x,weak_y,weak_z\n";
  for (const ScoredKeyframe& k : scored) {
    const LidarDegeneracy& d = k.lidar;
    csv += std::to_string(k.stamp) + ",lidar," +
           PrintfText("%.4f,1,%.0f,%.5f,%.5f,%.4f,%.4f,%.4f\n", d.score, d.matches, d.translation_isotropy,
                      d.rotation_isotropy, d.weak_translation.x(), d.weak_translation.y(),
                      d.weak_translation.z());
  }
  if (Status s = WriteTextFileAtomically(folder / "reliability.csv", csv); !s.ok()) return s;
  std::vector<std::string> written = {"reliability.csv"};
  if (scored.empty()) return written;
  std::vector<double> seconds, scores;
  for (const ScoredKeyframe& k : scored) {
    seconds.push_back(ToSeconds(k.stamp - scored.front().stamp));
    scores.push_back(k.lidar.score);
  }
  std::error_code error;
  std::filesystem::create_directories(folder / "plots", error);
  if (error) return Status::Error((folder / "plots").string() + ": cannot create: " + error.message());
  const std::string plot = "plots/reliability_lidar.png";
  if (Status s = WriteSeriesPlot((folder / plot).string(), seconds, scores, "LiDAR degeneracy D",
                                 SeriesLevel{kDegenerateReported, "reported as degenerate from here"},
                                 "LiDAR degeneracy per keyframe (0: every direction pinned, 1: one free)",
                                 "time since the first keyframe (s)", "D");
      !s.ok())
    return s;
  written.push_back(plot);
  return written;
}

}  // namespace uf::pipeline
