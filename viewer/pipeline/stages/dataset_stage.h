// The dataset stage of `ultrafusion run`: one pass over the dataset as `ultrafusion info` makes it (streams,
// message counts, rates, gaps, points per scan, reader warnings), for the report's dataset summary; its
// LiDAR scan count also gives the odometry stage its total, hence a remaining time. `ultrafusion info` prints
// it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>

#include "viewer/app/dataset_config.h"
#include "viewer/app/report/info_report.h"

namespace uf::app {

// Called every few messages with the messages read so far.
using MessageProgress = std::function<void(std::int64_t messages)>;

// Reads every message of the dataset once. An unreadable or damaged dataset is an error naming it.
Expected<DatasetSummary> SummarizeDataset(const std::filesystem::path& path, const DatasetConfig& config,
                                          const MessageProgress& progress = {});

// The size of a dataset's files in bytes (the file itself, or everything under the folder).
std::int64_t DatasetBytes(const std::filesystem::path& path);

}  // namespace uf::app
