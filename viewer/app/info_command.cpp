#include "viewer/app/info_command.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>

#include "odometry/io/dataset_reader.h"
#include "viewer/app/dataset_config.h"
#include "viewer/app/exit_codes.h"
#include "viewer/app/info_report.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct InfoArguments {
  std::string dataset, config, format;
  bool json = false;
};

std::int64_t DatasetBytes(const fs::path& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return static_cast<std::int64_t>(fs::file_size(path, ec));
  std::int64_t total = 0;
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file(ec)) total += static_cast<std::int64_t>(it->file_size(ec));
  }
  return total;
}

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

// One line on stderr every two seconds on a terminal, so long bags show progress.
class Progress {
 public:
  void Update(std::int64_t messages, Stamp stamp) {
    if (!enabled_ || Clock::now() - last_ < std::chrono::seconds(2)) return;
    last_ = Clock::now();
    std::fprintf(stderr, "\rinfo: %lld messages read, at stamp %s s", static_cast<long long>(messages),
                 FormatSeconds(stamp).c_str());
    shown_ = true;
  }
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_ = isatty(STDERR_FILENO);
  bool shown_ = false;
  Clock::time_point last_ = Clock::now();
};

Expected<DatasetSummary> Summarize(const fs::path& path, const DatasetConfig& config) {
  const Clock::time_point start = Clock::now();
  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(path, config.reader);
  if (!opened) return opened.status();
  DatasetReader& reader = **opened;
  const std::size_t stream_count = reader.description().streams.size();
  StreamDiagnosticsOptions diagnostics_options;
  diagnostics_options.reorder_window = config.stream.reorder_window;
  StreamDiagnostics diagnostics(stream_count, diagnostics_options);
  std::vector<PointCounter> points(stream_count);
  Progress progress;
  std::int64_t messages = 0;
  while (true) {
    Expected<std::optional<Measurement>> next = reader.Next();
    if (!next) return next.status();
    if (!next->has_value()) break;
    const Measurement& m = **next;
    diagnostics.Add(m.stream, StampOf(m.data));
    if (const auto* scan = std::get_if<LidarScan>(&m.data)) points[m.stream].Add(scan->points.size());
    progress.Update(++messages, StampOf(m.data));
  }
  DatasetSummary summary;
  summary.description = reader.description();
  summary.warnings = reader.warnings();
  for (std::size_t s = 0; s < stream_count; ++s) {
    StreamSummary stream{summary.description.streams[s], diagnostics.Report(static_cast<int>(s)),
                         std::nullopt};
    if (points[s].scans > 0) {
      stream.points_per_scan =
          PointCountRange{points[s].min, points[s].max, double(points[s].total) / points[s].scans};
    }
    summary.streams.push_back(std::move(stream));
  }
  summary.bytes = DatasetBytes(path);
  summary.read_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

int RunInfo(const InfoArguments& arguments) {
  DatasetConfig config;
  if (!arguments.config.empty()) {
    Expected<DatasetConfig> loaded = LoadDatasetConfig(arguments.config);
    if (!loaded) return ReportError(loaded.status());
    config = *loaded;
  }
  if (!arguments.format.empty()) {
    Expected<DatasetFormat> format = ParseDatasetFormat(arguments.format);
    if (!format) return ReportError(format.status());
    config.reader.format = *format;
  }
  Expected<DatasetSummary> summary = Summarize(arguments.dataset, config);
  if (!summary) return ReportError(summary.status());
  if (arguments.json) {
    PrintDatasetJson(std::cout, *summary);
  } else {
    PrintDatasetTable(std::cout, *summary);
  }
  return kExitOk;
}

}  // namespace

Subcommand AddInfoCommand(CLI::App& app) {
  auto arguments = std::make_shared<InfoArguments>();
  CLI::App* info =
      app.add_subcommand("info", "Show the sensor streams of a dataset and check their time stamps");
  info->add_option("DATASET", arguments->dataset,
                   "ROS1 .bag file, or a KITTI-style, EuRoC or ultrafusion folder")
      ->required();
  info->add_flag("--json", arguments->json, "Print JSON instead of the table");
  info->add_option("--config", arguments->config,
                   "YAML configuration with a dataset: section (topics, units, ...)")
      ->check(CLI::ExistingFile);
  info->add_option("--format", arguments->format, "Dataset format, overriding detection and the config")
      ->check(CLI::IsMember({"auto", "rosbag", "kitti", "euroc", "ultrafusion"}));
  return {info, [arguments] { return RunInfo(*arguments); }};
}

}  // namespace uf::app
