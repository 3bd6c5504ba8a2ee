// KITTI raw drives (the "sync" and "extract" packages): a drive folder with velodyne_points/, oxts/ and
// image_00..03/, its calibration one level up in the date folder. See folder_readers.h for what is read.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "odometry/io/folders/csv_sources.h"
#include "odometry/io/folders/folder_common.h"
#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/folders/kitti_raw_calibration.h"
#include "odometry/io/folders/kitti_raw_frames.h"
#include "odometry/io/folders/kitti_raw_oxts.h"
#include "odometry/io/folders/point_cloud_files.h"
#include "odometry/types/azimuth_convention.h"
#include "odometry/types/rings_from_storage_order.h"

namespace uf {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kScanExtensions = {".bin", ".bin.xz", ".txt"};

// The extract package's ASCII scans: `x y z reflectance` per line.
Expected<LidarScan> ReadAsciiScan(const fs::path& path, std::int64_t& dropped) {
  std::ifstream in(path);
  if (!in) return Status::Error(path.string() + ": cannot open file");
  LidarScan scan;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream words(line);
    double v[4];
    if (!(words >> v[0] >> v[1] >> v[2] >> v[3]))
      return Status::Error(path.string() + ":" + std::to_string(number) + ": expected x y z reflectance");
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3])) {
      ++dropped;
      continue;
    }
    scan.points.push_back({static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                           static_cast<float>(v[3])});
  }
  return scan;
}

// The sweep of scan `frame`: from timestamps_start/_end.txt when both have its line, else half a period
// either side of its timestamps.txt stamp (the instant the head faced forward).
struct SweepTimes {
  std::optional<std::vector<std::optional<Stamp>>> start, end;
  Stamp period = 0;

  std::pair<Stamp, Stamp> Of(const KittiFrame& frame) const {
    const auto at = [&](const auto& stamps) -> std::optional<Stamp> {
      if (!stamps || frame.index >= static_cast<std::int64_t>(stamps->size())) return std::nullopt;
      return (*stamps)[frame.index];
    };
    const std::optional<Stamp> first = at(start), last = at(end);
    if (first && last && *first < frame.stamp && frame.stamp < *last) return {*first, *last};
    return {frame.stamp - period / 2, frame.stamp - period / 2 + period};
  }
};

Expected<std::unique_ptr<StreamSource>> LidarSource(const fs::path& folder, const DatasetOptions& options,
                                                    StreamInfo& stream) {
  KittiListingNotes notes;
  auto frames = ListKittiFrames(folder, kScanExtensions, notes);
  if (!frames) return frames.status();
  if (frames->empty())
    return Status::Error((folder / "data").string() + ": no scans with a stamp (NNNNNNNNNN.bin files)");
  SweepTimes sweeps;
  sweeps.period = FromSeconds(options.lidar_sweep_period_s);
  auto start = ReadOptionalKittiTimestamps(folder / "timestamps_start.txt");
  if (!start) return start.status();
  auto end = ReadOptionalKittiTimestamps(folder / "timestamps_end.txt");
  if (!end) return end.status();
  sweeps.start = std::move(*start);
  sweeps.end = std::move(*end);
  const std::string extension = frames->front().file.filename().string().substr(10);
  stream.message_type = "kitti raw velodyne " + extension;
  const bool derive = options.derive_point_times_from_azimuth;
  const AzimuthConvention convention = options.point_time_convention.value_or(kClockwiseFromBehind);
  stream.point_time = derive ? PointTimeConvention::kAzimuth : PointTimeConvention::kNone;
  if (derive) stream.azimuth_convention = convention;
  const std::string name = stream.name;
  auto load = [sweeps, derive, convention, name](
                  const KittiFrame& frame, StreamInfo&,
                  WarningLog& warnings) -> Expected<std::optional<MeasurementData>> {
    PointCloudFileInfo info;
    std::int64_t dropped = 0;
    auto scan = frame.file.extension() == ".txt" ? ReadAsciiScan(frame.file, dropped)
                                                 : ReadKittiBin(frame.file, &info);
    if (!scan) {  // one damaged file of a long drive: skip it, say so
      warnings.Add(name, "damaged scan files skipped (" + scan.error() + ")");
      return std::optional<MeasurementData>();
    }
    DeriveRingsFromStorageOrder(*scan);
    dropped += info.dropped_non_finite;
    if (dropped > 0) warnings.Add(name, "points with NaN/Inf values dropped", dropped);
    const auto [first, last] = sweeps.Of(frame);
    scan->stamp = first;
    scan->end = last;
    if (derive) DeriveAzimuthPointTimes(*scan, last - first, convention);
    return std::optional<MeasurementData>(std::move(*scan));
  };
  return std::unique_ptr<StreamSource>(std::make_unique<KittiFrameSource>(
      std::move(*frames), notes, stream.name, "scan files", std::move(load)));
}

// One OXTS source per use (IMU samples, GNSS fixes): each reads the records itself.
template <typename Convert>
Expected<std::unique_ptr<StreamSource>> OxtsSource(std::vector<KittiFrame> frames,
                                                   const KittiListingNotes& notes, const std::string& stream,
                                                   Convert convert) {
  auto load = [convert](const KittiFrame& frame, StreamInfo&,
                        WarningLog&) -> Expected<std::optional<MeasurementData>> {
    auto record = ReadOxtsFile(frame.file);
    if (!record) return record.status();
    return std::optional<MeasurementData>(convert(*record, frame.stamp));
  };
  return std::unique_ptr<StreamSource>(
      std::make_unique<KittiFrameSource>(std::move(frames), notes, stream, "OXTS records", std::move(load)));
}

// Width and height from a PNG's IHDR chunk; nullopt when the bytes are not a PNG.
std::optional<std::pair<int, int>> PngSize(const std::vector<std::uint8_t>& bytes) {
  if (ImageFormatOf(bytes) != "png" || bytes.size() < 24) return std::nullopt;
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
  };
  return std::pair<int, int>(static_cast<int>(be32(16)), static_cast<int>(be32(20)));
}

Expected<std::unique_ptr<StreamSource>> CameraSource(std::vector<KittiFrame> frames,
                                                     const KittiListingNotes& notes,
                                                     const StreamInfo& stream) {
  const int width = stream.camera_model->width(), height = stream.camera_model->height();
  const int camera = stream.camera;
  auto load = [width, height, camera](const KittiFrame& frame, StreamInfo&,
                                      WarningLog&) -> Expected<std::optional<MeasurementData>> {
    std::ifstream in(frame.file, std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && !in) return Status::Error(frame.file.string() + ": cannot read the image");
    const auto size = PngSize(bytes);
    if (!size) return Status::Error(frame.file.string() + ": not a PNG image");
    if (size->first != width || size->second != height)
      return Status::Error(frame.file.string() + ": image is " + std::to_string(size->first) + " x " +
                           std::to_string(size->second) +
                           " px, the calibration (calib_cam_to_cam.txt) says " + std::to_string(width) +
                           " x " + std::to_string(height));
    CameraFrame image;
    image.stamp = frame.stamp;
    image.camera = camera;
    image.encoded.format = "png";
    image.encoded.bytes = std::move(bytes);
    return std::optional<MeasurementData>(std::move(image));
  };
  return std::unique_ptr<StreamSource>(
      std::make_unique<KittiFrameSource>(std::move(frames), notes, stream.name, "images", std::move(load)));
}

// Typical spacing of the frames' stamps, as a rate.
double MedianRate(const std::vector<KittiFrame>& frames) {
  std::vector<Stamp> steps;
  for (std::size_t i = 1; i < frames.size(); ++i)
    steps.push_back((frames[i].stamp - frames[i - 1].stamp) /
                    std::max<std::int64_t>(frames[i].index - frames[i - 1].index, 1));
  if (steps.empty()) return 0;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return 1.0 / ToSeconds(steps[steps.size() / 2]);
}

// The OXTS INS poses of the IMU (KITTI devkit convertOxtsToPose), relative to the first.
Expected<Trajectory> OxtsReference(const std::vector<KittiFrame>& frames) {
  Trajectory reference;
  double scale = 0;
  SE3 T_first_world;
  for (const KittiFrame& frame : frames) {
    auto record = ReadOxtsFile(frame.file);
    if (!record) return record.status();
    if (reference.empty()) {
      scale = std::cos(record->latitude_deg * M_PI / 180.0);
      T_first_world = OxtsMercatorPose(*record, scale).inverse();
    }
    reference.stamps.push_back(frame.stamp);
    reference.poses.push_back(T_first_world * OxtsMercatorPose(*record, scale));
  }
  return reference;
}

bool IsDirectory(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

}  // namespace

bool IsKittiRawDrive(const fs::path& path) {
  return IsDirectory(path / "velodyne_points") || IsDirectory(path / "oxts");
}

Expected<std::unique_ptr<DatasetReader>> OpenKittiRawDrive(const fs::path& path,
                                                           const DatasetOptions& options) {
  const double period = options.lidar_sweep_period_s;
  if (!(period > 0 && period <= 2.0))
    return Status::Error("dataset option lidar_sweep_period_s must be in (0, 2] s, found " +
                         std::to_string(period));
  if (!IsKittiRawDrive(path))
    return Status::Error(path.string() + ": not a KITTI raw drive: no velodyne_points/ or oxts/ folder");
  const fs::path drive = fs::absolute(path).lexically_normal();
  const fs::path date_folder = (drive.has_filename() ? drive : drive.parent_path()).parent_path();
  const bool rectified = !FolderName(path).ends_with("_extract");
  auto rig = ReadKittiRawRig(date_folder);
  if (!rig) return rig.status();

  DatasetDescription description;
  description.path = path;
  description.format = DatasetFormat::kKittiRaw;
  std::vector<std::unique_ptr<StreamSource>> sources;
  const auto add = [&](StreamInfo stream, std::unique_ptr<StreamSource> source) {
    description.streams.push_back(std::move(stream));
    sources.push_back(std::move(source));
  };

  if (IsDirectory(path / "velodyne_points")) {
    StreamInfo lidar;
    lidar.name = "velodyne_points";
    lidar.kind = SensorKind::kLidar;
    lidar.nominal_rate_hz = 1.0 / period;
    lidar.T_body_sensor = rig->T_imu_velo;
    auto source = LidarSource(path / "velodyne_points", options, lidar);
    if (!source) return source.status();
    add(std::move(lidar), std::move(*source));
  }
  if (IsDirectory(path / "oxts")) {
    KittiListingNotes notes;
    auto frames = ListKittiFrames(path / "oxts", {".txt"}, notes);
    if (!frames) return frames.status();
    if (frames->empty())
      return Status::Error((path / "oxts" / "data").string() + ": no OXTS records with a stamp");
    auto reference = OxtsReference(*frames);
    if (!reference) return reference.status();
    const double rate = MedianRate(*frames);
    StreamInfo imu;
    imu.name = "oxts/imu";
    imu.kind = SensorKind::kImu;
    imu.message_type = "kitti raw oxts";
    imu.imu_accel_unit = "m/s^2";
    imu.nominal_rate_hz = rate;
    imu.T_body_sensor = SE3();
    if (rate < 50)
      imu.note = "ax ay az, wx wy wz sampled at " + std::to_string(static_cast<int>(std::lround(rate))) +
                 " Hz (the sync package resamples the OXTS to the LiDAR frames): enough for gravity and "
                 "smooth driving, too slow to follow vibration or sharp turns between samples; the extract "
                 "package has the 100 Hz stream";
    StreamInfo gnss = imu;
    gnss.name = "oxts/gnss";
    gnss.kind = SensorKind::kGnss;
    gnss.message_type = "kitti raw oxts";
    gnss.note =
        "the OXTS INS position (GNSS blended with its IMU, not raw receiver fixes; pos_accuracy as "
        "the horizontal sigma)";
    gnss.imu_accel_unit.clear();
    auto imu_source = OxtsSource(*frames, notes, imu.name, OxtsImuSample);
    auto gnss_source = OxtsSource(*frames, notes, gnss.name, OxtsGnssFix);
    if (!imu_source) return imu_source.status();
    if (!gnss_source) return gnss_source.status();
    description.reference =
        ReferenceTrajectory{std::move(*reference), static_cast<int>(description.streams.size()),
                            "the OXTS INS poses (GNSS + IMU, KITTI devkit convertOxtsToPose)"};
    add(std::move(imu), std::move(*imu_source));
    add(std::move(gnss), std::move(*gnss_source));
  }
  for (int index = 0; index < 4; ++index) {
    const fs::path folder = path / (std::to_string(index).insert(0, "image_0"));
    if (!IsDirectory(folder / "data")) continue;  // timestamps only: the drive was downloaded without them
    KittiListingNotes notes;
    auto frames = ListKittiFrames(folder, {".png"}, notes);
    if (!frames) return frames.status();
    if (frames->empty()) continue;
    auto camera = ReadKittiRawCamera(date_folder, *rig, index, rectified);
    if (!camera) return camera.status();
    StreamInfo stream;
    stream.name = std::to_string(index).insert(0, "image_0");
    stream.kind = SensorKind::kCamera;
    stream.message_type = rectified ? "kitti raw png (rectified)" : "kitti raw png (raw, distorted)";
    stream.camera = index;
    stream.camera_model = camera->model;
    stream.T_body_sensor = camera->T_imu_camera;
    stream.nominal_rate_hz = MedianRate(*frames);
    auto source = CameraSource(std::move(*frames), notes, stream);
    if (!source) return source.status();
    add(std::move(stream), std::move(*source));
  }
  if (sources.empty())
    return Status::Error(path.string() + ": no velodyne_points/data, oxts/data or image_0N/data with frames");
  auto reader = MergedStreamsReader::Create(std::move(description), std::move(sources));
  if (!reader) return reader.status();
  return std::unique_ptr<DatasetReader>(std::move(*reader));
}

}  // namespace uf
