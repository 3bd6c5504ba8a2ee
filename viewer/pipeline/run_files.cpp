#include "viewer/pipeline/run_files.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>

#include "odometry/eval/plots.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/trajectory_file.h"

namespace uf::pipeline {

TimingSummary SummarizeTimings(std::vector<double> ms) {
  TimingSummary summary;
  summary.steps = ms.size();
  if (ms.empty()) return summary;
  std::sort(ms.begin(), ms.end());
  const std::size_t n = ms.size();
  summary.mean = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(n);
  summary.median = n % 2 == 1 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
  // Nearest rank: rank ceil(0.95 n), 1-based.
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(n)));
  summary.p95 = ms[std::clamp<std::size_t>(rank, 1, n) - 1];
  summary.max = ms.back();
  return summary;
}

Status WriteTrajectoryFiles(const std::filesystem::path& folder, const Trajectory& trajectory) {
  if (Status s = WriteTumTrajectory((folder / "trajectory.tum").string(), trajectory); !s.ok()) return s;
  return WriteKittiTrajectory((folder / "trajectory_kitti.txt").string(), trajectory);
}

Status WriteTimingJson(const std::filesystem::path& path, const TimingSummary& timing, std::int64_t skipped,
                       std::int64_t warnings, const std::string& step,
                       const std::optional<StageTimes>& stages) {
  nlohmann::json json = {
      {step + "s", timing.steps},
      {"ms_per_" + step,
       {{"mean", timing.mean}, {"median", timing.median}, {"p95", timing.p95}, {"max", timing.max}}},
      {"skipped", skipped},
      {"warnings", warnings}};
  if (stages)
    json["stage_ms_mean"] = {{"prepare", stages->prepare},
                             {"associate", stages->associate},
                             {"register", stages->register_scan},
                             {"window", stages->window},
                             {"map", stages->map},
                             {"marginalize", stages->marginalize}};
  return WriteTextFileAtomically(path, json.dump(2) + "\n");
}

Status WriteTimingPlot(const std::filesystem::path& png, const std::vector<Stamp>& stamps,
                       const std::vector<double>& milliseconds, const std::string& step) {
  std::vector<double> seconds;
  seconds.reserve(stamps.size());
  for (Stamp stamp : stamps) seconds.push_back(ToSeconds(stamp - stamps.front()));
  return WriteErrorPlot(png.string(), seconds, milliseconds, ComputeStats(milliseconds), "Time per " + step,
                        "time from the first " + step + " [s]", "processing time [ms]");
}

Status WriteTextFileAtomically(const std::filesystem::path& path, const std::string& text) {
  AtomicFileWriter writer(path.string());
  if (Status s = writer.status(); !s.ok()) return s;
  writer.stream() << text;
  return writer.Commit();
}

Status WriteBinaryFileAtomically(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  AtomicFileWriter writer(path.string());
  if (Status s = writer.status(); !s.ok()) return s;
  writer.stream().write(reinterpret_cast<const char*>(bytes.data()),
                        static_cast<std::streamsize>(bytes.size()));
  return writer.Commit();
}

}  // namespace uf::pipeline
