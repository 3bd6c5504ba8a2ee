#include "viewer/pipeline/stages/dataset_stage.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "odometry/io/dataset_reader.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// Points per scan, accumulated over a LiDAR stream.
struct PointCounter {
  std::int64_t scans = 0, total = 0;
  std::int64_t min = std::numeric_limits<std::int64_t>::max(), max = 0;

  void Add(std::int64_t points) {
    ++scans;
    total += points;
    min = std::min(min, points);
    max = std::max(max, points);
  }
};

}  // namespace

std::int64_t DatasetBytes(const fs::path& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return static_cast<std::int64_t>(fs::file_size(path, ec));
  std::int64_t total = 0;
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) total += static_cast<std::int64_t>(it->file_size(ec));
  return total;
}

Expected<DatasetSummary> SummarizeDataset(const fs::path& path, const DatasetConfig& config,
                                          const MessageProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(path, config.reader);
  if (!opened) return opened.status();
  DatasetReader& reader = **opened;
  const std::size_t stream_count = reader.description().streams.size();
  StreamDiagnosticsOptions diagnostics_options;
  diagnostics_options.reorder_window = config.stream.reorder_window;
  StreamDiagnostics diagnostics(stream_count, diagnostics_options);
  std::vector<PointCounter> points(stream_count);
  std::int64_t messages = 0;
  while (true) {
    Expected<std::optional<Measurement>> next = reader.Next();
    if (!next) return next.status();
    if (!next->has_value()) break;
    const Measurement& m = **next;
    diagnostics.Add(m.stream, StampOf(m.data));
    if (const auto* scan = std::get_if<LidarScan>(&m.data))
      points[m.stream].Add(static_cast<std::int64_t>(scan->points.size()));
    ++messages;
    if (progress && messages % 64 == 0) progress(messages);
  }
  if (progress) progress(messages);
  DatasetSummary summary;
  summary.description = reader.description();
  summary.warnings = reader.warnings();
  for (std::size_t s = 0; s < stream_count; ++s) {
    StreamSummary stream{summary.description.streams[s], diagnostics.Report(static_cast<int>(s)),
                         std::nullopt};
    if (points[s].scans > 0)
      stream.points_per_scan = PointCountRange{points[s].min, points[s].max,
                                               static_cast<double>(points[s].total) / points[s].scans};
    summary.streams.push_back(std::move(stream));
  }
  summary.bytes = DatasetBytes(path);
  summary.read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

Expected<DatasetStageOutput> RunDatasetStage(const fs::path& dataset, const DatasetConfig& config,
                                             int paced_stream, StageContext& context) {
  context.SetUnit("messages");
  Expected<DatasetSummary> summary =
      SummarizeDataset(dataset, config, [&](std::int64_t messages) { context.Progress(messages); });
  if (!summary) return summary.status();
  DatasetStageOutput output;
  const auto paced = static_cast<std::size_t>(paced_stream);
  if (paced < summary->streams.size()) output.paced_messages = summary->streams[paced].time.count;
  output.summary = std::move(*summary);
  return output;
}

}  // namespace uf::pipeline
