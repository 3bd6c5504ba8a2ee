#include "odometry/io/rosbag/rosbag_reader.h"

#include <algorithm>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include "odometry/io/rosbag/bag_file.h"
#include "odometry/io/rosbag/bag_message_decode.h"
#include "odometry/io/rosbag/bag_streams.h"
#include "odometry/io/rosbag/imu_unit.h"
#include "odometry/io/warning_log.h"

namespace uf {
namespace {

class RosBagReader final : public DatasetReader {
 public:
  RosBagReader(std::unique_ptr<bag::BagFile> bag, bag::BagStreamPlan plan, const std::filesystem::path& path,
               const DatasetOptions& options);

  const DatasetDescription& description() const override { return description_; }
  Expected<std::optional<Measurement>> Next() override;
  const std::vector<ReadWarning>& warnings() const override { return warnings_.entries(); }

  // Settles the unit of every IMU stream with imu_accel_unit kAuto from the first second of its samples, by
  // a second pass over the start of the bag, so that Next() can then deliver everything in record order.
  Status DetectImuUnits();

 private:
  Status ReadRecord();  // reads one record; what it yields goes to ready_
  Status Finish();      // end of the bag: releases the held IMU samples
  void Accept(int stream, bag::DecodedMessage decoded);
  Status AcceptImu(int stream, const ImuSample& sample);
  void EmitReadyImu(int stream);  // moves imu_ready_ to ready_
  void Warn(int stream, const std::string& what, std::int64_t count = 1);

  std::unique_ptr<bag::BagFile> bag_;
  DatasetDescription description_;
  std::vector<bag::MessageType> types_;  // per stream
  std::unordered_map<std::uint32_t, int> stream_of_connection_;
  std::vector<std::optional<ImuUnitGate>> imu_gates_;  // per stream, IMU streams only
  std::vector<bool> seen_;                             // per stream: a message has been read
  LidarDecodeOptions lidar_options_;

  std::deque<Measurement> ready_;
  std::vector<ImuSample> imu_ready_;  // scratch for the gates
  WarningLog warnings_;
  Status failure_;
  bool ended_ = false;
};

RosBagReader::RosBagReader(std::unique_ptr<bag::BagFile> bag, bag::BagStreamPlan plan,
                           const std::filesystem::path& path, const DatasetOptions& options)
    : bag_(std::move(bag)), stream_of_connection_(std::move(plan.stream_of_connection)) {
  description_.path = path;
  description_.format = DatasetFormat::kRosBag;
  for (bag::BagStream& stream : plan.streams) {
    types_.push_back(stream.type);
    imu_gates_.emplace_back();
    if (stream.info.kind == SensorKind::kImu) {
      imu_gates_.back().emplace(options.imu_accel_unit, stream.info.name);
    }
    description_.streams.push_back(std::move(stream.info));
  }
  seen_.assign(description_.streams.size(), false);
  lidar_options_.derive_point_times_from_azimuth = options.derive_point_times_from_azimuth;
  lidar_options_.sweep_period_s = options.lidar_sweep_period_s;
  lidar_options_.azimuth_convention = options.point_time_convention.value_or(kClockwiseFromFirstPoint);
}

Status RosBagReader::DetectImuUnits() {
  // Enough for the first second of any IMU in any bag we know of; an IMU that starts later than this is
  // settled in Next(), holding back its own first second.
  constexpr std::uint64_t kMaxBytesScanned = 256 << 20;
  auto unresolved = [&] {
    return std::any_of(imu_gates_.begin(), imu_gates_.end(),
                       [](const auto& gate) { return gate && !gate->resolved(); });
  };
  if (!unresolved()) return Status();
  Expected<std::unique_ptr<bag::BagFile>> probe = bag::BagFile::Open(description_.path);
  if (!probe.ok()) return Status();  // the main pass meets the same damage and reports it
  std::uint64_t scanned = 0;
  while (unresolved() && scanned < kMaxBytesScanned) {
    const Expected<std::optional<bag::MessageRecord>> record = (*probe)->Next();
    if (!record.ok() || !record->has_value()) break;
    scanned += (*record)->data.size();
    const auto stream_of = stream_of_connection_.find((*record)->connection);
    if (stream_of == stream_of_connection_.end()) continue;
    std::optional<ImuUnitGate>& gate = imu_gates_[stream_of->second];
    if (!gate || gate->resolved()) continue;
    const Expected<bag::DecodedMessage> decoded =
        bag::DecodeBagMessage(types_[stream_of->second], (*record)->data, (*record)->time, lidar_options_);
    if (!decoded.ok()) continue;  // counted when the main pass reads it
    imu_ready_.clear();
    if (Status pushed = gate->Push(std::get<ImuSample>(decoded->data), imu_ready_); !pushed.ok()) {
      return Status::Error(description_.path.string() + ": " + pushed.message());
    }
  }
  // Decide from what was held when the scan stopped early (end of the bag or its byte budget).
  for (std::size_t stream = 0; stream < imu_gates_.size(); ++stream) {
    std::optional<ImuUnitGate>& gate = imu_gates_[stream];
    if (!gate) continue;
    imu_ready_.clear();
    if (Status flushed = gate->Flush(imu_ready_); !flushed.ok()) {
      return Status::Error(description_.path.string() + ": " + flushed.message());
    }
    if (gate->resolved()) {
      description_.streams[stream].imu_accel_unit = std::string(ImuAccelUnitName(gate->unit()));
    }
  }
  return Status();
}

Expected<std::optional<Measurement>> RosBagReader::Next() {
  while (ready_.empty()) {
    if (!failure_.ok()) return failure_;
    if (ended_) return std::optional<Measurement>();
    if (Status step = ReadRecord(); !step.ok()) failure_ = step;
  }
  Measurement next = std::move(ready_.front());
  ready_.pop_front();
  return std::optional<Measurement>(std::move(next));
}

Status RosBagReader::ReadRecord() {
  const Expected<std::optional<bag::MessageRecord>> record = bag_->Next();
  if (!record.ok()) return record.status();
  if (!record->has_value()) return Finish();
  const bag::MessageRecord& message = **record;
  const auto stream_of = stream_of_connection_.find(message.connection);
  if (stream_of == stream_of_connection_.end()) return Status();  // a topic not read
  const int stream = stream_of->second;
  Expected<bag::DecodedMessage> decoded =
      bag::DecodeBagMessage(types_[stream], message.data, message.time, lidar_options_);
  if (!decoded.ok()) {
    Warn(stream, decoded.error());
    return Status();
  }
  if (std::holds_alternative<ImuSample>(decoded->data)) {
    const ImuSample sample = std::get<ImuSample>(decoded->data);
    Accept(stream, std::move(decoded).value());
    return AcceptImu(stream, sample);
  }
  if (auto* frame = std::get_if<CameraFrame>(&decoded->data)) {
    frame->camera = description_.streams[stream].camera;
  }
  Measurement measurement{stream, std::move(decoded->data)};
  Accept(stream, std::move(decoded).value());
  ready_.push_back(std::move(measurement));
  return Status();
}

// Fills what the first message of a stream tells, and counts the recoverable damage.
void RosBagReader::Accept(int stream, bag::DecodedMessage decoded) {
  StreamInfo& info = description_.streams[stream];
  if (!seen_[stream]) {
    seen_[stream] = true;
    info.frame_id = decoded.frame_id;
  }
  if (info.kind == SensorKind::kLidar && info.point_time == PointTimeConvention::kNone) {
    info.point_time = decoded.point_time;
    info.point_time_field = decoded.point_time_field;
    if (info.point_time == PointTimeConvention::kAzimuth)
      info.azimuth_convention = lidar_options_.azimuth_convention;
  }
  if (decoded.header_stamp_zero) Warn(stream, "header stamp is zero; the record time was used");
  if (decoded.non_finite_points > 0) Warn(stream, "NaN points dropped", decoded.non_finite_points);
  if (!decoded.point_times_dropped.empty()) Warn(stream, decoded.point_times_dropped);
}

Status RosBagReader::AcceptImu(int stream, const ImuSample& sample) {
  ImuUnitGate& gate = *imu_gates_[stream];
  imu_ready_.clear();
  const Status pushed = gate.Push(sample, imu_ready_);
  if (!pushed.ok()) return Status::Error(description_.path.string() + ": " + pushed.message());
  if (gate.resolved()) {
    description_.streams[stream].imu_accel_unit = std::string(ImuAccelUnitName(gate.unit()));
  }
  EmitReadyImu(stream);
  return Status();
}

Status RosBagReader::Finish() {
  ended_ = true;
  for (std::size_t stream = 0; stream < imu_gates_.size(); ++stream) {
    if (!imu_gates_[stream]) continue;
    imu_ready_.clear();
    const Status flushed = imu_gates_[stream]->Flush(imu_ready_);
    if (!flushed.ok()) return Status::Error(description_.path.string() + ": " + flushed.message());
    if (imu_gates_[stream]->resolved()) {
      description_.streams[stream].imu_accel_unit = std::string(ImuAccelUnitName(imu_gates_[stream]->unit()));
    }
    EmitReadyImu(static_cast<int>(stream));
  }
  return Status();
}

void RosBagReader::EmitReadyImu(int stream) {
  for (const ImuSample& sample : imu_ready_) {
    Measurement& measurement = ready_.emplace_back();
    measurement.stream = stream;
    measurement.data = sample;
  }
  imu_ready_.clear();
}

// One warning per (stream, kind of damage): the kind is the text before the parenthesised values of the
// first message that showed it, which stay in `what` as an example.
void RosBagReader::Warn(int stream, const std::string& what, std::int64_t count) {
  warnings_.Add(description_.streams[stream].name, what, count);
}

}  // namespace

Expected<std::unique_ptr<DatasetReader>> OpenRosBag(const std::filesystem::path& path,
                                                    const DatasetOptions& options) {
  Expected<std::unique_ptr<bag::BagFile>> bag = bag::BagFile::Open(path);
  if (!bag.ok()) return bag.status();
  Expected<bag::BagStreamPlan> plan = bag::PlanBagStreams((*bag)->connections(), options, path.string());
  if (!plan.ok()) return plan.status();
  auto reader =
      std::make_unique<RosBagReader>(std::move(bag).value(), std::move(plan).value(), path, options);
  if (Status detected = reader->DetectImuUnits(); !detected.ok()) return detected;
  return std::unique_ptr<DatasetReader>(std::move(reader));
}

}  // namespace uf
