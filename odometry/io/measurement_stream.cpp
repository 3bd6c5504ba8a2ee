#include "odometry/io/measurement_stream.h"

#include <cassert>

namespace uf {

Expected<MeasurementStream> MeasurementStream::Create(DatasetReader& reader,
                                                      MeasurementStreamOptions options) {
  const std::vector<StreamInfo>& streams = reader.description().streams;
  std::vector<Stamp> offsets(streams.size(), 0);
  for (const auto& [key, offset] : options.time_offsets) {
    bool matched = false;
    for (std::size_t i = 0; i < streams.size(); ++i) {
      if (streams[i].name == key) {
        offsets[i] = offset;
        matched = true;
      }
    }
    if (matched) continue;
    for (std::size_t i = 0; i < streams.size(); ++i) {
      if (SensorKindName(streams[i].kind) != key) continue;
      // A stream's own name takes precedence over its kind.
      if (!options.time_offsets.contains(streams[i].name)) offsets[i] = offset;
      matched = true;
    }
    if (!matched) {
      return Status::Error("time offset for '" + key + "': no stream or sensor kind of that name in " +
                           reader.description().path.string() +
                           " (streams: " + StreamNames(reader.description()) + ")");
    }
  }
  // The calibration file's offsets (StreamInfo::time_offset) add to the configured ones.
  for (std::size_t i = 0; i < streams.size(); ++i) offsets[i] += streams[i].time_offset;
  return MeasurementStream(reader, std::move(options), std::move(offsets));
}

MeasurementStream::MeasurementStream(DatasetReader& reader, MeasurementStreamOptions options,
                                     std::vector<Stamp> offsets)
    : reader_(&reader),
      options_(std::move(options)),
      offsets_(std::move(offsets)),
      buffers_(offsets_.size()),
      last_accepted_(offsets_.size()),
      drops_(offsets_.size()) {}

Expected<std::optional<Measurement>> MeasurementStream::Next() {
  while (true) {
    if (std::optional<int> stream = ReadyStream()) return std::optional<Measurement>(Release(*stream));
    if (reader_done_) {
      finished_ = true;
      return std::optional<Measurement>();
    }
    if (Status status = Pull(); !status.ok()) return status;
  }
}

Status MeasurementStream::Pull() {
  Expected<std::optional<Measurement>> next = reader_->Next();
  if (!next) return next.status();
  if (!next->has_value()) {
    reader_done_ = true;
    return {};
  }
  Accept(std::move(**next));
  return {};
}

void MeasurementStream::Accept(Measurement measurement) {
  assert(measurement.stream >= 0 && std::size_t(measurement.stream) < buffers_.size());
  const int s = measurement.stream;
  ShiftStamp(measurement.data, offsets_[s]);
  const Stamp stamp = StampOf(measurement.data);
  // Order within the stream first, then against what has already been handed out.
  if (last_accepted_[s] && stamp < *last_accepted_[s]) {
    ++drops_[s].backwards;
    return;
  }
  if (last_accepted_[s] && stamp == *last_accepted_[s]) {
    ++drops_[s].duplicates;
    return;
  }
  last_accepted_[s] = stamp;
  if (last_released_ && stamp < *last_released_) {
    ++drops_[s].late;
    return;
  }
  if (!newest_read_ || stamp > *newest_read_) newest_read_ = stamp;
  buffers_[s].push_back(std::move(measurement));
  ++buffered_;
}

// k-way merge: the oldest head may go once no stream can still deliver something older, i.e. every
// stream has a buffered head, or the quiet streams would be lagging the newest stamp by more than the
// reorder window (anything they send later counts as late), or the buffer bound is reached.
std::optional<int> MeasurementStream::ReadyStream() const {
  std::optional<int> oldest;
  for (std::size_t s = 0; s < buffers_.size(); ++s) {
    if (buffers_[s].empty()) continue;
    if (!oldest || StampOf(buffers_[s].front().data) < StampOf(buffers_[*oldest].front().data)) {
      oldest = static_cast<int>(s);
    }
  }
  if (!oldest || reader_done_ || buffered_ >= options_.max_buffered) return oldest;
  const Stamp candidate = StampOf(buffers_[*oldest].front().data);
  if (newest_read_ && candidate <= *newest_read_ - options_.reorder_window) return oldest;
  for (const auto& buffer : buffers_) {
    if (buffer.empty()) return std::nullopt;
  }
  return oldest;
}

Measurement MeasurementStream::Release(int stream) {
  Measurement measurement = std::move(buffers_[stream].front());
  buffers_[stream].pop_front();
  --buffered_;
  last_released_ = StampOf(measurement.data);
  ++drops_[stream].delivered;
  return measurement;
}

std::vector<ReadWarning> MeasurementStream::warnings() const {
  std::vector<ReadWarning> warnings = reader_->warnings();
  const std::vector<StreamInfo>& streams = reader_->description().streams;
  for (std::size_t s = 0; s < drops_.size(); ++s) {
    const StreamDropCounts& d = drops_[s];
    if (d.backwards) warnings.push_back({streams[s].name, "stamps going backwards dropped", d.backwards});
    if (d.duplicates) warnings.push_back({streams[s].name, "duplicate stamps dropped", d.duplicates});
    if (d.late) {
      warnings.push_back(
          {streams[s].name, "measurements arriving later than the reorder window dropped", d.late});
    }
  }
  return warnings;
}

}  // namespace uf
