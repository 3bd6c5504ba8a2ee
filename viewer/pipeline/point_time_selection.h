// Which convention the point times of a LiDAR stream without per-point time are derived with, for `run`
// and `info`: the one `dataset.point_time_convention` names, else (auto) the one the check
// (odometry/estimator/point_times/point_time_check.h) finds on the first scans. The caller then opens the
// dataset with it (DatasetOptions::point_time_convention), so that every reader of the run derives the same
// times.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/estimator/point_times/point_time_check.h"
#include "odometry/types/azimuth_convention.h"
#include "viewer/app/config/dataset_config.h"

namespace uf::pipeline {

struct PointTimeSelection {
  std::string stream;  // the LiDAR stream's name
  // The convention the times are derived with; nullopt: the project's format, times kept as stored.
  std::optional<AzimuthConvention> convention;
  std::string source;  // "dataset.point_time_convention", "the check", "stored in the dataset"
  std::optional<estimator::PointTimeCheckResult> check;  // when the check ran

  // One line for the reports and the log: "counter-clockwise from behind (chosen by the check on the first
  // scans: ...reason...)".
  std::string Line() const;
};

// For the first LiDAR stream of `dataset`, when its scans get azimuth-derived times (the first scan read
// says so): the configured convention, or the check's choice over the first scans (`lo_config`: the run's
// lo: settings; the check runs it LiDAR-only). nullopt: no LiDAR stream, or its scans carry their own
// times or none. Errors: the dataset's (unreadable, damaged) and the odometry configuration's.
Expected<std::optional<PointTimeSelection>> SelectPointTimes(
    const std::filesystem::path& dataset, const app::DatasetConfig& config,
    const estimator::LidarOdometryConfig& lo_config, const estimator::PointTimeCheckOptions& options = {});

}  // namespace uf::pipeline
