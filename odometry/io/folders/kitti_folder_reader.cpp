// KITTI-style LiDAR folder: scan files in name order, one times.txt line per scan, ground truth beside it.
#include <algorithm>
#include <cmath>

#include "odometry/io/folders/folder_common.h"
#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/folders/merged_streams.h"
#include "odometry/io/folders/point_cloud_files.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/types/rings_from_storage_order.h"

namespace uf {
namespace {

namespace fs = std::filesystem;

bool IsScanFile(const fs::path& file) { return file.extension() == ".bin" || file.extension() == ".pcd"; }

// One scan file per Advance(); the file is read only in Load().
class KittiScanSource : public StreamSource {
 public:
  KittiScanSource(std::vector<fs::path> files, std::vector<Stamp> stamps, std::string stream,
                  const DatasetOptions& options)
      : files_(std::move(files)),
        stamps_(std::move(stamps)),
        stream_(std::move(stream)),
        sweep_period_(FromSeconds(options.lidar_sweep_period_s)),
        derive_times_(options.derive_point_times_from_azimuth),
        convention_(options.point_time_convention.value_or(kClockwiseFromBehind)),
        stamp_at_middle_(options.folder_scan_stamp == ScanStampPosition::kSweepMiddle) {}

  Expected<bool> Advance() override { return ++next_ <= files_.size(); }
  Stamp stamp() const override { return stamps_[next_ - 1]; }

  Expected<std::optional<MeasurementData>> Load(StreamInfo& info, WarningLog& warnings) override {
    const fs::path& file = files_[next_ - 1];
    PointCloudFileInfo file_info;
    auto scan = file.extension() == ".pcd" ? ReadPcdFile(file, &file_info) : ReadKittiBin(file, &file_info);
    if (!scan) return scan.status();
    DeriveRingsFromStorageOrder(*scan);
    if (file_info.dropped_non_finite > 0)
      warnings.Add(stream_, "points with NaN/Inf values dropped", file_info.dropped_non_finite);
    switch (file_info.point_time) {
      case PointTimeConvention::kAbsoluteSeconds:
      case PointTimeConvention::kAbsoluteNanoseconds:
        break;  // the file's own absolute point times win over times.txt
      case PointTimeConvention::kRelativeSeconds:
      case PointTimeConvention::kRelativeNanoseconds:
        scan->stamp += stamp();  // relative to the times.txt stamp
        scan->end += stamp();
        break;
      default:
        scan->stamp = stamp() - (stamp_at_middle_ ? sweep_period_ / 2 : 0);  // the sweep start
        scan->end = scan->stamp + sweep_period_;
        if (derive_times_) DeriveAzimuthPointTimes(*scan, sweep_period_, convention_);
        file_info.point_time = derive_times_ ? PointTimeConvention::kAzimuth : PointTimeConvention::kNone;
        break;
    }
    if (next_ == 1) {  // what the data tells about the stream
      info.point_time = file_info.point_time;
      info.point_time_field = file_info.point_time_field;
      if (info.point_time != PointTimeConvention::kAzimuth) info.azimuth_convention.reset();
    }
    return std::optional<MeasurementData>(std::move(*scan));
  }

 private:
  std::vector<fs::path> files_;
  std::vector<Stamp> stamps_;
  std::string stream_;
  Stamp sweep_period_;
  bool derive_times_;
  AzimuthConvention convention_;  // of the derived times
  bool stamp_at_middle_;          // times.txt stamps the middle of the sweep (KITTI), not its start
  std::size_t next_ = 0;          // files_[next_ - 1] is the current record
};

// groundtruth*.tum, poses.txt, poses/<folder>.txt, the only .txt in poses/, or ../../poses/<folder>.txt.
std::optional<fs::path> FindGroundTruth(const fs::path& folder) {
  std::vector<fs::path> tum;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.starts_with("groundtruth") && entry.path().extension() == ".tum")
      tum.push_back(entry.path());
  }
  if (!tum.empty()) return *std::min_element(tum.begin(), tum.end());
  const std::string sequence = FolderName(folder) + ".txt";
  for (const fs::path& candidate : {folder / "poses.txt", folder / "poses" / sequence})
    if (fs::is_regular_file(candidate, error)) return candidate;
  std::vector<fs::path> poses;
  for (const auto& entry : fs::directory_iterator(folder / "poses", error))
    if (entry.is_regular_file() && entry.path().extension() == ".txt") poses.push_back(entry.path());
  if (poses.size() == 1) return poses.front();
  const fs::path dataset_layout = fs::absolute(folder).lexically_normal().parent_path().parent_path();
  if (fs::is_regular_file(dataset_layout / "poses" / sequence, error))
    return dataset_layout / "poses" / sequence;
  return std::nullopt;
}

}  // namespace

Expected<std::unique_ptr<DatasetReader>> OpenKittiFolder(const fs::path& path,
                                                         const DatasetOptions& options) {
  const double period = options.lidar_sweep_period_s;
  if (!(period > 0 && period <= 2.0))
    return Status::Error("dataset option lidar_sweep_period_s must be in (0, 2] s, found " +
                         std::to_string(period));
  std::error_code error;
  fs::path scan_folder = path / "velodyne";
  if (!fs::is_directory(scan_folder, error)) scan_folder = path / "lidar";
  if (!fs::is_directory(scan_folder, error))
    return Status::Error(path.string() +
                         ": not a KITTI-style folder: no velodyne/ or lidar/ folder of scans");

  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(scan_folder, error))
    if (entry.is_regular_file() && IsScanFile(entry.path())) files.push_back(entry.path());
  if (error) return Status::Error(scan_folder.string() + ": cannot list the folder: " + error.message());
  if (files.empty()) return Status::Error(scan_folder.string() + ": no .bin or .pcd scan files");
  std::sort(files.begin(), files.end());

  const fs::path times_path = path / "times.txt";
  if (!fs::is_regular_file(times_path, error))
    return Status::Error(times_path.string() + ": missing; a KITTI-style folder needs one stamp per scan");
  auto stamps = ReadTimesFile(times_path.string());
  if (!stamps) return stamps.status();
  if (stamps->size() != files.size())
    return Status::Error(times_path.string() + ": " + std::to_string(stamps->size()) + " stamps for " +
                         std::to_string(files.size()) + " scan files in " + scan_folder.string() +
                         "; the counts must agree");

  const bool all_bin =
      std::all_of(files.begin(), files.end(), [](auto& f) { return f.extension() == ".bin"; });
  const bool all_pcd =
      std::all_of(files.begin(), files.end(), [](auto& f) { return f.extension() == ".pcd"; });
  StreamInfo stream;
  stream.name = RelativeName(scan_folder, path);
  stream.kind = SensorKind::kLidar;
  stream.message_type = all_bin ? "kitti velodyne .bin" : all_pcd ? "kitti velodyne .pcd" : "kitti .bin/.pcd";
  stream.nominal_rate_hz = 1.0 / period;
  stream.point_time =
      options.derive_point_times_from_azimuth ? PointTimeConvention::kAzimuth : PointTimeConvention::kNone;
  if (options.derive_point_times_from_azimuth)
    stream.azimuth_convention = options.point_time_convention.value_or(kClockwiseFromBehind);
  DatasetDescription description;
  description.path = path;
  description.format = DatasetFormat::kKittiFolder;
  description.streams.push_back(stream);
  description.ground_truth = FindGroundTruth(path);

  std::vector<std::unique_ptr<StreamSource>> sources;
  sources.push_back(
      std::make_unique<KittiScanSource>(std::move(files), std::move(*stamps), stream.name, options));
  auto reader = MergedStreamsReader::Create(std::move(description), std::move(sources));
  if (!reader) return reader.status();
  return std::unique_ptr<DatasetReader>(std::move(*reader));
}

}  // namespace uf
