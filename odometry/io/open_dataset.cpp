// Format detection and dispatch to the reader of each dataset format.
#include <system_error>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/recalibrated_reader.h"
#include "odometry/io/rosbag/rosbag_reader.h"

namespace uf {
namespace fs = std::filesystem;
namespace {

bool IsDirectory(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

bool IsFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

Expected<DatasetFormat> DetectFormat(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return Status::Error(path.string() + ": no such file or folder");
  if (IsFile(path)) {
    if (path.extension() == ".bag") return DatasetFormat::kRosBag;
    return Status::Error(path.string() +
                         ": not a dataset (a file must be a ROS1 .bag; folders may be KITTI-style, KITTI raw "
                         "drives, EuRoC or ultrafusion datasets)");
  }
  if (IsFile(path / "dataset.yaml")) return DatasetFormat::kUltrafusion;
  if (IsDirectory(path / "mav0") || path.filename() == "mav0") return DatasetFormat::kEuroc;
  if (IsDirectory(path / "velodyne") || IsDirectory(path / "lidar")) return DatasetFormat::kKittiFolder;
  if (IsKittiRawDrive(path)) return DatasetFormat::kKittiRaw;
  return Status::Error(path.string() +
                       ": unrecognised dataset folder (expected dataset.yaml, mav0/, velodyne/, lidar/, "
                       "velodyne_points/ or oxts/ inside; or pass a .bag file; the format can also be set in the config)");
}

}  // namespace

namespace {

Expected<std::unique_ptr<DatasetReader>> OpenFormat(const fs::path& path, const DatasetOptions& options) {
  DatasetFormat format = options.format;
  if (format == DatasetFormat::kAuto) {
    Expected<DatasetFormat> detected = DetectFormat(path);
    if (!detected) return detected.status();
    format = *detected;
  }
  switch (format) {
    case DatasetFormat::kRosBag:
      return OpenRosBag(path, options);
    case DatasetFormat::kKittiFolder:
      return OpenKittiFolder(path, options);
    case DatasetFormat::kKittiRaw:
      return OpenKittiRawDrive(path, options);
    case DatasetFormat::kEuroc:
      return OpenEurocFolder(path, options);
    case DatasetFormat::kUltrafusion:
      return OpenUltrafusionFolder(path, options);
    case DatasetFormat::kAuto:
      break;
  }
  return Status::Error(path.string() + ": no reader for the dataset format");
}

}  // namespace

std::string StreamNames(const DatasetDescription& description) {
  std::string names;
  for (const StreamInfo& s : description.streams) names += (names.empty() ? "" : ", ") + s.name;
  return names;
}

Expected<std::unique_ptr<DatasetReader>> OpenDataset(const fs::path& path, const DatasetOptions& options) {
  Expected<std::unique_ptr<DatasetReader>> reader = OpenFormat(path, options);
  if (!reader || options.calibration_file.empty()) return reader;
  return WithCalibrationFile(std::move(*reader), options.calibration_file);
}

}  // namespace uf
