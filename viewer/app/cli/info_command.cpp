#include "viewer/app/cli/info_command.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "odometry/io/dataset_reader.h"
#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/config_file.h"
#include "viewer/app/config/dataset_config.h"
#include "viewer/app/report/info_report.h"
#include "viewer/pipeline/stages/dataset_stage.h"

namespace uf::app {

using pipeline::DatasetSummary;
using pipeline::SummarizeDataset;
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct InfoArguments {
  std::string dataset, config, format;
  bool json = false;
};

// One line on stderr every two seconds on a terminal, so long bags show progress.
class Progress {
 public:
  void Update(std::int64_t messages) {
    if (!enabled_ || Clock::now() - last_ < std::chrono::seconds(2)) return;
    last_ = Clock::now();
    std::fprintf(stderr, "\rinfo: %lld messages read", static_cast<long long>(messages));
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

int RunInfo(const InfoArguments& arguments) {
  DatasetConfig config;
  estimator::LidarOdometryConfig odometry;  // the lo: settings the point time check runs with
  if (!arguments.config.empty()) {
    Expected<ConfigFile> loaded = LoadConfigFile(arguments.config);
    if (!loaded) return ReportError(loaded.status());
    config = loaded->dataset;
    odometry = loaded->odometry;
  }
  if (!arguments.format.empty()) {
    Expected<DatasetFormat> format = ParseDatasetFormat(arguments.format);
    if (!format) return ReportError(format.status());
    config.reader.format = *format;
  }
  // Azimuth-derived point times: the configured convention, or the one the check finds on the first scans
  // (a few seconds), with which the dataset is then read.
  Expected<std::optional<pipeline::PointTimeSelection>> times =
      pipeline::SelectPointTimes(arguments.dataset, config, odometry);
  if (!times) return ReportError(times.status());
  if (*times && (*times)->convention) config.reader.point_time_convention = (*times)->convention;
  Progress progress;
  Expected<DatasetSummary> summary =
      SummarizeDataset(arguments.dataset, config, [&](std::int64_t messages) { progress.Update(messages); });
  if (!summary) return ReportError(summary.status());
  summary->point_times = std::move(*times);
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
