// Time diagnostics of a dataset's streams, as `ultrafusion info` reports them: message count, rate, first
// and last stamp, gaps, stamps going backwards or repeating, messages arriving out of order with respect
// to the other streams, and rate jitter, with a verdict per stream.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "odometry/io/measurement.h"

namespace uf {

enum class StreamVerdict { kOk, kWarning, kBad };

std::string_view StreamVerdictName(StreamVerdict verdict);  // "ok", "warning", "bad"

struct StreamTimeReport {
  std::int64_t count = 0;
  Stamp first = 0, last = 0;
  double rate_hz = 0;          // (count - 1) / (last - first) over the stamps in storage order
  double median_period_s = 0;  // median of the positive stamp differences
  double jitter_percent = 0;   // standard deviation of the positive differences / their mean, %
  std::int64_t gaps = 0;       // differences longer than gap_factor x the median period
  double largest_gap_s = 0;
  std::int64_t backwards = 0;     // stamp earlier than the previous message of the stream
  std::int64_t duplicates = 0;    // stamp equal to the previous message of the stream
  std::int64_t out_of_order = 0;  // stamp older than (newest stamp of any stream so far - reorder window)
  StreamVerdict verdict = StreamVerdict::kOk;
  std::vector<std::string> findings;  // why the verdict is not ok, one line each
};

struct StreamDiagnosticsOptions {
  double gap_factor = 3.0;               // a difference above gap_factor x median period is a gap
  double jitter_warning_percent = 20;    // rate jitter above this is a warning
  Stamp reorder_window = 1'000'000'000;  // as MeasurementStreamOptions::reorder_window
};

class StreamDiagnostics {
 public:
  explicit StreamDiagnostics(std::size_t stream_count, StreamDiagnosticsOptions options = {});

  // Feed every measurement in storage order (as DatasetReader::Next delivers them).
  void Add(int stream, Stamp stamp);

  // The report of one stream (computes the statistics; call once all measurements were added).
  StreamTimeReport Report(int stream) const;

 private:
  struct Accumulator {
    std::int64_t count = 0;
    Stamp first = 0, previous = 0, min = 0, max = 0;
    std::vector<float> periods_s;  // positive stamp differences (4 bytes each keeps hours of 1 kHz IMU small)
    std::int64_t backwards = 0, duplicates = 0, out_of_order = 0;
  };
  StreamDiagnosticsOptions options_;
  std::vector<Accumulator> streams_;
  std::optional<Stamp> newest_;
};

}  // namespace uf
