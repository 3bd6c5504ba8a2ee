// The one interface every dataset format sits behind (after Basalt's dataset_io): describe what is
// inside, then stream the measurements out in storage order with bounded memory. MeasurementStream turns
// that into a single time-ordered sequence for the estimator.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/io/dataset_options.h"
#include "odometry/io/measurement.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/geodetic.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

// How a LiDAR stream stamps its points, as recognised from the field name and type.
enum class PointTimeConvention {
  kNone,                    // no per-point time
  kRelativeSeconds,         // Velodyne `time` float32, s after the scan stamp
  kRelativeNanoseconds,     // Ouster `t` uint32, ns after the scan stamp
  kAbsoluteSeconds,         // Hesai/Robosense `timestamp` float64, absolute s
  kAbsoluteNanoseconds,     // Livox driver2 `timestamp` float64, absolute ns
  kLivoxOffsetNanoseconds,  // livox_ros_driver CustomMsg `offset_time` uint32, ns after timebase
  kAzimuth,                 // none in the data: derived from azimuth (flagged in LidarScan)
};

std::string_view PointTimeConventionName(PointTimeConvention convention);

struct StreamInfo {
  std::string name;  // ROS topic, or the path of the stream's file/folder relative to the dataset
  SensorKind kind = SensorKind::kImu;
  std::string message_type;  // "sensor_msgs/PointCloud2", "kitti velodyne .bin", "euroc imu csv", ...
  std::string frame_id;      // ROS frame id when the data names one
  int camera = -1;           // camera streams: index in the rig, in order of appearance
  // LiDAR: the per-point time field found ("time", "t", "timestamp", "offset_time") and its convention.
  std::string point_time_field;
  PointTimeConvention point_time = PointTimeConvention::kNone;
  // kAzimuth: the convention the reader derived the times with (nullopt: the project's format, as stored).
  std::optional<AzimuthConvention> azimuth_convention;
  // IMU: the acceleration unit the data was found in ("m/s^2" or "g"); samples are always delivered in m/s^2.
  std::string imu_accel_unit;
  // Calibration that came with the data (EuRoC sensor.yaml, the project's dataset.yaml), if any.
  std::optional<SE3> T_body_sensor;
  // Added to the stream's stamps by MeasurementStream (beside dataset.time_offsets_s), ns: set from
  // DatasetOptions::calibration_file (recalibrated_reader.h), 0 otherwise.
  Stamp time_offset = 0;
  std::shared_ptr<const CameraModel> camera_model;  // camera streams: intrinsics and distortion
  double nominal_rate_hz = 0;                       // from the calibration file, 0 when unknown
  std::string note;  // what a user should know about the stream's data (`info` prints it), e.g. its limits
};

// Damage the reader recovered from by skipping data: shown as a warning with the number of messages lost.
struct ReadWarning {
  std::string stream;  // topic or file
  std::string
      what;  // "NaN points dropped", "PointCloud2 data size disagrees with width*height*point_step", ...
  std::int64_t count = 0;
};

// Reference poses a reader derives from the data itself when no ground-truth file comes with it (KITTI raw:
// the OXTS INS solution), used like a ground-truth file that would stand beside the data.
struct ReferenceTrajectory {
  Trajectory poses;  // T_world_sensor of stream `stream`'s sensor (the world: that sensor at the first pose)
  int stream = -1;   // index into DatasetDescription::streams
  std::string source;  // what the poses are, for `info` and the report
};

struct DatasetDescription {
  std::filesystem::path path;
  DatasetFormat format = DatasetFormat::kAuto;
  std::vector<StreamInfo> streams;
  // TUM/KITTI/EuRoC ground truth found beside the data: poses of the body frame B, the frame the streams'
  // T_body_sensor are given in (a KITTI folder: its only stream, the LiDAR; EuRoC: the IMU; the project's own
  // format: dataset.yaml's body, the simulator's IMU).
  std::optional<std::filesystem::path> ground_truth;
  std::optional<GeodeticOrigin> ground_truth_enu_origin;  // its world is ENU at this point, when known
  std::optional<ReferenceTrajectory> reference;           // when the reader derived one (see above)
};

class DatasetReader {
 public:
  virtual ~DatasetReader() = default;

  // Streams found when the dataset was opened. Fields learnt from the data itself (point time convention,
  // IMU unit) are filled once the first message of the stream has been read.
  virtual const DatasetDescription& description() const = 0;

  // The next measurement in storage order (for a bag: record order; for folders: merged by stamp), or
  // std::nullopt at the end. An error is unrecoverable damage (truncated file, corrupt chunk); after it the
  // reader returns the same error again.
  virtual Expected<std::optional<Measurement>> Next() = 0;

  // Recoverable damage met so far, one entry per (stream, what).
  virtual const std::vector<ReadWarning>& warnings() const = 0;
};

// The names of the description's streams, ", "-separated, for error messages.
std::string StreamNames(const DatasetDescription& description);

// Detects the format from the path (unless options.format says it) and opens the dataset:
//   *.bag file                          -> ROS1 bag
//   folder with velodyne/ or lidar/ + times.txt -> KITTI-style folder
//   folder with velodyne_points/ or oxts/ -> KITTI raw drive (calib_*.txt one level up)
//   folder with mav0/ (or the mav0 folder itself) -> EuRoC ASL
//   folder with dataset.yaml            -> the project's own format
Expected<std::unique_ptr<DatasetReader>> OpenDataset(const std::filesystem::path& path,
                                                     const DatasetOptions& options = {});

}  // namespace uf
