// A DatasetReader that replays a scripted list of measurements (and optionally fails at a given point):
// lets the tests of everything downstream of the readers control storage order exactly.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"

namespace uf::test {

class ScriptedReader : public DatasetReader {
 public:
  ScriptedReader(std::vector<StreamInfo> streams, std::vector<Measurement> script)
      : script_(std::move(script)) {
    description_.path = "scripted";
    description_.streams = std::move(streams);
  }

  // Next() returns this error once `index` measurements have been delivered.
  void FailAt(std::size_t index, std::string message) {
    fail_at_ = index;
    error_ = std::move(message);
  }

  std::size_t delivered() const { return next_; }  // measurements handed out so far

  const DatasetDescription& description() const override { return description_; }
  const std::vector<ReadWarning>& warnings() const override { return warnings_; }

  Expected<std::optional<Measurement>> Next() override {
    if (fail_at_ && next_ >= *fail_at_) return Status::Error(error_);
    if (next_ == script_.size()) return std::optional<Measurement>();
    return std::optional<Measurement>(script_[next_++]);
  }

 private:
  DatasetDescription description_;
  std::vector<Measurement> script_;
  std::vector<ReadWarning> warnings_;
  std::size_t next_ = 0;
  std::optional<std::size_t> fail_at_;
  std::string error_;
};

inline Measurement Imu(int stream, Stamp stamp) {
  ImuSample s;
  s.stamp = stamp;
  return {stream, s};
}

inline Measurement Gnss(int stream, Stamp stamp) {
  GnssFix f;
  f.stamp = stamp;
  return {stream, f};
}

inline Measurement Scan(int stream, Stamp stamp, Stamp end) {
  LidarScan s;
  s.stamp = stamp;
  s.end = end;
  return {stream, s};
}

inline StreamInfo Info(std::string name, SensorKind kind) {
  StreamInfo info;
  info.name = std::move(name);
  info.kind = kind;
  return info;
}

}  // namespace uf::test
