#include "viewer/pipeline/point_time_selection.h"

#include "odometry/io/dataset_reader.h"
#include "odometry/io/dataset_sensors.h"

namespace uf::pipeline {
namespace {

Expected<std::optional<PointTimeSelection>> None() { return std::optional<PointTimeSelection>(); }

}  // namespace

std::string PointTimeSelection::Line() const {
  if (!convention)
    return "as stored in the dataset (the convention they were derived with is not recorded; "
           "dataset.point_time_convention derives them again)";
  const std::string text = AzimuthConventionText(*convention);
  if (!check) return text + " (set by " + source + ")";
  return text + " (" + source + " on the first scans: " + check->reason + ")";
}

Expected<std::optional<PointTimeSelection>> SelectPointTimes(
    const std::filesystem::path& dataset, const app::DatasetConfig& config,
    const estimator::LidarOdometryConfig& lo_config, const estimator::PointTimeCheckOptions& options) {
  if (!config.reader.derive_point_times_from_azimuth) return None();
  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(dataset, config.reader);
  if (!opened) return opened.status();
  DatasetReader& reader = **opened;
  const int lidar = FindSensors(reader.description()).lidar;
  if (lidar < 0) return None();
  std::optional<PointTimeSelection> selection;
  std::optional<estimator::PointTimeCheck> check;
  // The scans of the LiDAR stream in storage order until the check has enough of them (a plain loop rather
  // than ForEachMeasurement: it stops early).
  while (true) {
    Expected<std::optional<Measurement>> next = reader.Next();
    if (!next) return next.status();
    if (!next->has_value()) break;
    const auto* scan = std::get_if<LidarScan>(&(*next)->data);
    if (!scan || (*next)->stream != lidar) continue;
    if (!selection) {  // the first scan tells how the stream is timed
      if (!scan->point_times_from_azimuth) return None();
      const StreamInfo& info = reader.description().streams[static_cast<std::size_t>(lidar)];
      selection = PointTimeSelection{info.name, info.azimuth_convention, "", std::nullopt};
      if (config.reader.point_time_convention) {
        selection->source = "dataset.point_time_convention";
        return selection;
      }
      if (!info.azimuth_convention) {
        selection->source = "stored in the dataset";
        return selection;
      }
      Expected<estimator::PointTimeCheck> created =
          estimator::PointTimeCheck::Create(lo_config, *info.azimuth_convention, options);
      if (!created) return created.status();
      check.emplace(std::move(*created));
    }
    if (Status s = check->Add(*scan); !s.ok()) return s;
    if (check->Done()) break;
  }
  if (!selection) return None();  // a LiDAR stream without scans
  selection->check = check->Decide();
  selection->convention = selection->check->chosen;
  selection->source = "chosen by the check";
  return selection;
}

}  // namespace uf::pipeline
