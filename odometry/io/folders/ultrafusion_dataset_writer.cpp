#include "odometry/io/folders/ultrafusion_dataset_writer.h"

#include <yaml-cpp/yaml.h>

#include <map>

#include "odometry/io/atomic_file.h"
#include "odometry/io/camera_calibration.h"
#include "odometry/io/folders/csv_sources.h"
#include "odometry/io/folders/folder_common.h"
#include "odometry/io/folders/lidar_record_file.h"
#include "odometry/io/folders/ultrafusion_format.h"
#include "odometry/io/image_decode.h"
#include "odometry/io/trajectory_file.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using ultrafusion_format::FormatNumber;

struct StreamFile {
  StreamInfo info;
  std::string file;  // relative to the dataset folder
  std::unique_ptr<AtomicFileWriter> out;
  bool has_last = false;
  Stamp last = 0;
};

const char* CsvHeader(SensorKind kind) {
  switch (kind) {
    case SensorKind::kImu:
      return "# stamp_ns,gx,gy,gz,ax,ay,az (rad/s, m/s^2, imu frame)\n";
    case SensorKind::kWheel:
      return "# stamp_ns,vx,vy,vz,wx,wy,wz (m/s, rad/s, wheel/base frame)\n";
    case SensorKind::kGnss:
      return "# stamp_ns,latitude_deg,longitude_deg,altitude_m,c00,c01,c02,c10,c11,c12,c20,c21,c22,status\n";
    case SensorKind::kCamera:
      return "# stamp_ns,filename\n";
    case SensorKind::kLidar:
      return "";
  }
  return "";
}

// stamp, then the numbers, comma-separated.
template <typename... Vectors>
std::string Row(Stamp stamp, const Vectors&... vectors) {
  std::string row = std::to_string(stamp);
  auto append = [&](const auto& v) {
    for (int i = 0; i < v.size(); ++i) {
      row += ',';
      row += FormatNumber(v[i]);
    }
  };
  (append(vectors), ...);
  return row;
}

}  // namespace

struct UltrafusionDatasetWriter::State {
  fs::path folder;
  std::vector<StreamFile> streams;
  bool has_ground_truth = false;
  std::optional<GeodeticOrigin> ground_truth_enu_origin;
  bool finished = false;

  Status Error(const std::string& what) const { return Status::Error(folder.string() + ": " + what); }
  Status WriteCamera(StreamFile& stream, const CameraFrame& frame);
  Status WriteDescription();
};

UltrafusionDatasetWriter::UltrafusionDatasetWriter(std::unique_ptr<State> state) : state_(std::move(state)) {}
UltrafusionDatasetWriter::UltrafusionDatasetWriter(UltrafusionDatasetWriter&&) noexcept = default;
UltrafusionDatasetWriter& UltrafusionDatasetWriter::operator=(UltrafusionDatasetWriter&&) noexcept = default;
UltrafusionDatasetWriter::~UltrafusionDatasetWriter() = default;

Expected<UltrafusionDatasetWriter> UltrafusionDatasetWriter::Create(const fs::path& folder,
                                                                    std::vector<StreamInfo> streams) {
  auto state = std::make_unique<State>();
  state->folder = folder;
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) return state->Error("cannot create the folder: " + error.message());
  if (fs::exists(folder / ultrafusion_format::kDescriptionFile, error))
    return state->Error("already holds a dataset (dataset.yaml); remove it or write elsewhere");
  if (streams.empty()) return state->Error("a dataset needs at least one stream");

  std::map<std::string, int> files_of_kind;
  std::vector<int> cameras;
  for (StreamInfo& info : streams) {
    std::string base = std::string(SensorKindName(info.kind));
    if (info.kind == SensorKind::kCamera) {
      if (info.camera < 0) info.camera = static_cast<int>(cameras.size());
      if (std::find(cameras.begin(), cameras.end(), info.camera) != cameras.end())
        return state->Error("two camera streams with camera index " + std::to_string(info.camera));
      cameras.push_back(info.camera);
      base = "cam" + std::to_string(info.camera);
    } else if (const int n = files_of_kind[base]++; n > 0) {
      base += std::to_string(n);
    }
    StreamFile stream;
    stream.file = info.kind == SensorKind::kCamera  ? base + "/" + base + ".csv"
                  : info.kind == SensorKind::kLidar ? base + ".bin"
                                                    : base + ".csv";
    if (info.name.empty()) info.name = base;
    for (const StreamFile& other : state->streams)
      if (other.info.name == info.name) return state->Error("two streams named '" + info.name + "'");
    if (info.kind == SensorKind::kCamera) fs::create_directories(folder / base, error);
    if (error) return state->Error("cannot create " + base + "/: " + error.message());
    stream.info = std::move(info);
    stream.out = std::make_unique<AtomicFileWriter>((folder / stream.file).string());
    if (Status s = stream.out->status(); !s.ok()) return s;
    stream.out->stream() << CsvHeader(stream.info.kind);
    state->streams.push_back(std::move(stream));
  }
  return UltrafusionDatasetWriter(std::move(state));
}

Status UltrafusionDatasetWriter::Write(const Measurement& measurement) {
  State& state = *state_;
  if (state.finished) return state.Error("Write() after Finish()");
  if (measurement.stream < 0 || measurement.stream >= static_cast<int>(state.streams.size()))
    return state.Error("no stream " + std::to_string(measurement.stream));
  StreamFile& stream = state.streams[measurement.stream];
  const SensorKind kind = KindOf(measurement.data);
  if (kind != stream.info.kind)
    return state.Error("stream '" + stream.info.name + "' holds " +
                       std::string(SensorKindName(stream.info.kind)) + ", not " +
                       std::string(SensorKindName(kind)));
  const Stamp stamp = StampOf(measurement.data);
  if (stream.has_last && stamp <= stream.last)
    return state.Error("stream '" + stream.info.name + "': stamp " + std::to_string(stamp) +
                       " ns is not after the previous " + std::to_string(stream.last) + " ns");
  std::ofstream& out = stream.out->stream();
  if (const auto* imu = std::get_if<ImuSample>(&measurement.data)) {
    out << Row(stamp, imu->gyro, imu->acc) << '\n';
  } else if (const auto* wheel = std::get_if<WheelSample>(&measurement.data)) {
    out << Row(stamp, wheel->linear_velocity, wheel->angular_velocity) << '\n';
  } else if (const auto* fix = std::get_if<GnssFix>(&measurement.data)) {
    const Eigen::Matrix<double, 9, 1> covariance =
        Eigen::Matrix3d(fix->covariance_enu.transpose()).reshaped();  // row-major
    out << Row(stamp, Eigen::Vector3d(fix->latitude_deg, fix->longitude_deg, fix->altitude_m), covariance)
        << ',' << GnssFixStatusName(fix->status) << '\n';
  } else if (const auto* scan = std::get_if<LidarScan>(&measurement.data)) {
    if (scan->end < scan->stamp)
      return state.Error("stream '" + stream.info.name + "': scan end before stamp");
    const std::string record = EncodeLidarRecord(*scan);
    out.write(record.data(), static_cast<std::streamsize>(record.size()));
  } else if (const auto* frame = std::get_if<CameraFrame>(&measurement.data)) {
    if (Status s = state.WriteCamera(stream, *frame); !s.ok()) return s;
  }
  if (!out) return state.Error(stream.file + ": write failed (disk full?)");
  stream.has_last = true;
  stream.last = stamp;
  return {};
}

Status UltrafusionDatasetWriter::State::WriteCamera(StreamFile& stream, const CameraFrame& frame) {
  const std::string where = folder.string() + ": stream '" + stream.info.name + "'";
  std::vector<std::uint8_t> png;
  const std::vector<std::uint8_t>* bytes = &frame.encoded.bytes;
  std::string format = ImageFormatOf(frame.encoded.bytes);
  if (format.empty()) {
    if (frame.image.empty())
      return Status::Error(where + ": camera frame has neither PNG/JPEG bytes nor a decoded image");
    auto encoded = EncodePng(frame.image, where);
    if (!encoded) return encoded.status();
    png = std::move(*encoded);
    bytes = &png;
    format = "png";
  }
  const std::string name = std::to_string(frame.stamp) + (format == "png" ? ".png" : ".jpg");
  const fs::path image_folder = (folder / stream.file).parent_path();
  AtomicFileWriter image((image_folder / name).string());
  if (Status s = image.status(); !s.ok()) return s;
  image.stream().write(reinterpret_cast<const char*>(bytes->data()),
                       static_cast<std::streamsize>(bytes->size()));
  if (Status s = image.Commit(); !s.ok()) return s;
  stream.out->stream() << frame.stamp << ',' << name << '\n';
  return {};
}

Status UltrafusionDatasetWriter::WriteGroundTruth(const Trajectory& trajectory,
                                                  const std::optional<GeodeticOrigin>& enu_origin) {
  if (state_->finished) return state_->Error("WriteGroundTruth() after Finish()");
  if (Status s =
          WriteTumTrajectory((state_->folder / ultrafusion_format::kGroundTruthFile).string(), trajectory);
      !s.ok())
    return s;
  state_->has_ground_truth = true;
  state_->ground_truth_enu_origin = enu_origin;
  return {};
}

Status UltrafusionDatasetWriter::Finish() {
  State& state = *state_;
  if (state.finished) return state.Error("Finish() called twice");
  for (StreamFile& stream : state.streams)
    if (Status s = stream.out->Commit(); !s.ok()) return s;
  if (Status s = state.WriteDescription(); !s.ok()) return s;
  state.finished = true;
  return {};
}

Status UltrafusionDatasetWriter::State::WriteDescription() {
  YAML::Emitter yaml;
  yaml << YAML::BeginMap;
  yaml << YAML::Key << "format" << YAML::Value << std::string(ultrafusion_format::kFormat);
  yaml << YAML::Key << "version" << YAML::Value << ultrafusion_format::kVersion;
  yaml << YAML::Key << "streams" << YAML::Value << YAML::BeginSeq;
  for (const StreamFile& stream : streams) {
    const StreamInfo& info = stream.info;
    yaml << YAML::BeginMap;
    yaml << YAML::Key << "name" << YAML::Value << info.name;
    yaml << YAML::Key << "kind" << YAML::Value << std::string(SensorKindName(info.kind));
    yaml << YAML::Key << "file" << YAML::Value << stream.file;
    if (info.kind == SensorKind::kCamera) yaml << YAML::Key << "camera" << YAML::Value << info.camera;
    if (info.nominal_rate_hz > 0)
      yaml << YAML::Key << "rate_hz" << YAML::Value << FormatNumber(info.nominal_rate_hz);
    if (info.T_body_sensor) {
      yaml << YAML::Key << "T_body_sensor" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (double value : RowMajor(*info.T_body_sensor)) yaml << FormatNumber(value);
      yaml << YAML::EndSeq;
    }
    if (info.kind == SensorKind::kCamera && info.camera_model) {
      yaml << YAML::Key << "calibration" << YAML::Value << YAML::BeginMap;
      EmitCameraCalibration(yaml, *info.camera_model);
      yaml << YAML::EndMap;
    }
    yaml << YAML::EndMap;
  }
  yaml << YAML::EndSeq;
  if (has_ground_truth)
    yaml << YAML::Key << "ground_truth" << YAML::Value << std::string(ultrafusion_format::kGroundTruthFile);
  if (has_ground_truth && ground_truth_enu_origin) {
    const GeodeticOrigin& o = *ground_truth_enu_origin;
    yaml << YAML::Key << "ground_truth_enu_origin" << YAML::Value << YAML::Flow << YAML::BeginMap;
    yaml << YAML::Key << "latitude_deg" << YAML::Value << FormatNumber(o.latitude_deg);
    yaml << YAML::Key << "longitude_deg" << YAML::Value << FormatNumber(o.longitude_deg);
    yaml << YAML::Key << "height_m" << YAML::Value << FormatNumber(o.height_m);
    yaml << YAML::EndMap;
  }
  yaml << YAML::EndMap;
  if (!yaml.good()) return Error(std::string("cannot emit dataset.yaml: ") + yaml.GetLastError());
  AtomicFileWriter file((folder / ultrafusion_format::kDescriptionFile).string());
  if (Status s = file.status(); !s.ok()) return s;
  file.stream() << yaml.c_str() << '\n';
  return file.Commit();
}

}  // namespace uf
