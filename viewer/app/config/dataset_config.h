// The `dataset:` section of a configuration file: how to open a dataset (odometry/io's DatasetOptions) and
// how to merge its streams (MeasurementStreamOptions). Its keys, defaults and units are in docs/CONFIG.md;
// the file is read by LoadConfigFile (config_file.h).
#pragma once

#include <string>

#include "odometry/io/dataset_options.h"
#include "odometry/io/measurement_stream.h"

namespace uf::app {

struct DatasetConfig {
  DatasetOptions reader;
  MeasurementStreamOptions stream;
};

// "dataset:\n  format: kitti\n..." with every key (topics and time offsets when there are some).
std::string EmitDatasetConfig(const DatasetConfig& config);

// "auto | clockwise_from_behind | ... | none": the words of dataset.point_time_convention.
std::string PointTimeConventionWords();

// "rosbag", "kitti", ... as accepted by the config and the --format option.
Expected<DatasetFormat> ParseDatasetFormat(const std::string& name);

}  // namespace uf::app
