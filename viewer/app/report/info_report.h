// What `ultrafusion info` found in a dataset: per stream its description, time diagnostics and (LiDAR)
// points per scan; printed as a table or as JSON.
#pragma once

#include <ostream>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/stream_diagnostics.h"

namespace uf::app {

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
};

void PrintDatasetTable(std::ostream& out, const DatasetSummary& summary);
void PrintDatasetJson(std::ostream& out, const DatasetSummary& summary);

}  // namespace uf::app
