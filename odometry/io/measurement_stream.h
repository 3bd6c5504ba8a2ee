// One time-ordered sequence of measurements from a dataset, with an explicit end. Readers deliver in
// storage order (a bag's record order, roughly arrival time); sensor stamps lag arrival differently per
// sensor, so the stream merges the per-sensor sequences by stamp (k-way, streaming) and applies per-sensor
// time offsets on the way. Memory stays bounded: a quiet sensor holds the others back for at most
// `reorder_window` of stamp time and `max_buffered` measurements.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"

namespace uf {

struct MeasurementStreamOptions {
  // Offset added to the stamps of a stream, ns; keyed by stream name (topic or file, as in StreamInfo::name)
  // or by sensor kind name ("imu", "lidar", "camera", "wheel", "gnss") for every stream of that kind. A
  // stream name wins over its kind. Keys that match nothing are an error.
  std::map<std::string, Stamp> time_offsets;
  // How far (stamp time) a stream may lag the newest stamp read before the others are released without it.
  Stamp reorder_window = 1'000'000'000;  // 1 s
  // Hard bound on buffered measurements (LiDAR scans are large); when reached, the oldest is released.
  std::size_t max_buffered = 4096;
};

// What the stream dropped, per stream: stamps that would break the time order.
struct StreamDropCounts {
  std::int64_t delivered = 0;
  std::int64_t backwards = 0;   // stamp earlier than the previous one of the same stream
  std::int64_t duplicates = 0;  // stamp equal to the previous one of the same stream
  std::int64_t late = 0;        // arrived after later-stamped measurements had already been handed out
};

class MeasurementStream {
 public:
  // `reader` must outlive the stream. Fails when a time offset names no stream or kind.
  static Expected<MeasurementStream> Create(DatasetReader& reader, MeasurementStreamOptions options = {});

  // The next measurement, stamps non-decreasing (ties in stream order), or std::nullopt once every stream
  // is exhausted; reader errors pass through.
  Expected<std::optional<Measurement>> Next();

  bool finished() const { return finished_; }
  const DatasetDescription& description() const { return reader_->description(); }
  const std::vector<StreamDropCounts>& drop_counts() const { return drops_; }
  // The offset added to the stamps of stream `stream` (MeasurementStreamOptions::time_offsets resolved, plus
  // the stream's StreamInfo::time_offset), ns.
  Stamp time_offset(int stream) const { return offsets_[stream]; }
  // The reader's warnings plus one per stream and kind of drop, with counts.
  std::vector<ReadWarning> warnings() const;

 private:
  MeasurementStream(DatasetReader& reader, MeasurementStreamOptions options, std::vector<Stamp> offsets);

  Status Pull();                           // reads one measurement from the reader into its stream's buffer
  std::optional<int> ReadyStream() const;  // stream whose head can be released now, if any
  void Accept(Measurement measurement);
  Measurement Release(int stream);

  DatasetReader* reader_;
  MeasurementStreamOptions options_;
  std::vector<Stamp> offsets_;  // per stream
  std::vector<std::deque<Measurement>> buffers_;
  std::vector<std::optional<Stamp>> last_accepted_;  // per stream, after offset
  std::vector<StreamDropCounts> drops_;
  std::optional<Stamp> newest_read_;
  std::optional<Stamp> last_released_;
  std::size_t buffered_ = 0;
  bool reader_done_ = false;
  bool finished_ = false;
};

}  // namespace uf
