// The dataset stage of `ultrafusion run`: one pass over the dataset as `ultrafusion info` makes it (streams,
// message counts, rates, gaps, points per scan, reader warnings), for the report's dataset summary; the
// message count of the stream that paces the odometry (its LiDAR scans, or IMU samples in WIO) also gives
// the odometry stage its total, hence a remaining time. `ultrafusion info` prints
// it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/stream_diagnostics.h"
#include "viewer/app/config/dataset_config.h"
#include "viewer/pipeline/point_time_selection.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

using app::DatasetConfig;

struct PointCountRange {
  std::int64_t min = 0, max = 0;
  double mean = 0;
};

struct StreamSummary {
  StreamInfo info;
  StreamTimeReport time;
  std::optional<PointCountRange> points_per_scan;  // LiDAR streams with at least one scan
};

struct DatasetSummary {
  DatasetDescription description;
  std::vector<StreamSummary> streams;
  std::vector<ReadWarning> warnings;
  double read_seconds = 0;  // wall-clock time spent reading
  std::int64_t bytes = 0;   // size of the dataset's files
  // The LiDAR stream's azimuth convention and why (set by the caller that chose it: run, info).
  std::optional<PointTimeSelection> point_times;
};

// Called every few messages with the messages read so far.
using MessageProgress = std::function<void(std::int64_t messages)>;

// Reads every message of the dataset once. An unreadable or damaged dataset is an error naming it.
Expected<DatasetSummary> SummarizeDataset(const std::filesystem::path& path, const DatasetConfig& config,
                                          const MessageProgress& progress = {});

// The size of a dataset's files in bytes (the file itself, or everything under the folder).
std::int64_t DatasetBytes(const std::filesystem::path& path);

struct DatasetStageOutput {
  DatasetSummary summary;
  std::int64_t paced_messages = 0;  // of the stream `paced_stream`; the odometry stage's total
};

// The stage: SummarizeDataset with the progress in messages.
Expected<DatasetStageOutput> RunDatasetStage(const std::filesystem::path& dataset,
                                             const DatasetConfig& config, int paced_stream,
                                             StageContext& context);

}  // namespace uf::pipeline
