#include "odometry/io/stream_diagnostics.h"

#include <algorithm>
#include <cmath>

#include "odometry/types/printf_text.h"

namespace uf {
namespace {

double Percent(std::int64_t part, std::int64_t whole) { return whole ? 100.0 * part / whole : 0; }

double Median(std::vector<float> values) {
  const std::size_t n = values.size();
  std::nth_element(values.begin(), values.begin() + n / 2, values.end());
  double median = values[n / 2];
  if (n % 2 == 0) median = 0.5 * (median + *std::max_element(values.begin(), values.begin() + n / 2));
  return median;
}

void Judge(StreamTimeReport& r, const StreamDiagnosticsOptions& options) {
  auto raise = [&](StreamVerdict v, std::string finding) {
    r.verdict = std::max(r.verdict, v);
    r.findings.push_back(std::move(finding));
  };
  if (r.count == 0) return raise(StreamVerdict::kBad, "no messages");
  if (r.count == 1) raise(StreamVerdict::kWarning, "a single message: no rate");
  if (r.backwards) {
    raise(Percent(r.backwards, r.count) > 1 ? StreamVerdict::kBad : StreamVerdict::kWarning,
          PrintfText("%.0f stamps go backwards (%.2f%%); they are dropped", r.backwards,
                     Percent(r.backwards, r.count)));
  }
  if (r.duplicates) {
    raise(StreamVerdict::kWarning, PrintfText("%.0f duplicate stamps (%.2f%%); they are dropped",
                                              r.duplicates, Percent(r.duplicates, r.count)));
  }
  if (r.out_of_order) {
    raise(Percent(r.out_of_order, r.count) > 1 ? StreamVerdict::kBad : StreamVerdict::kWarning,
          PrintfText(
              "%.0f messages stored more than %.3g s after newer ones of other streams; they are dropped",
              r.out_of_order, options.reorder_window * 1e-9));
  }
  if (r.gaps) {
    raise(StreamVerdict::kWarning,
          PrintfText("%.0f gaps longer than %.3g x the median period", r.gaps, options.gap_factor) +
              PrintfText(", largest %.3f s", r.largest_gap_s));
  }
  if (r.jitter_percent > options.jitter_warning_percent) {
    raise(StreamVerdict::kWarning, PrintfText("rate jitter %.1f%% of the mean period", r.jitter_percent));
  }
}

}  // namespace

std::string_view StreamVerdictName(StreamVerdict verdict) {
  switch (verdict) {
    case StreamVerdict::kOk:
      return "ok";
    case StreamVerdict::kWarning:
      return "warning";
    case StreamVerdict::kBad:
      return "bad";
  }
  return "unknown";
}

StreamDiagnostics::StreamDiagnostics(std::size_t stream_count, StreamDiagnosticsOptions options)
    : options_(options), streams_(stream_count) {}

void StreamDiagnostics::Add(int stream, Stamp stamp) {
  Accumulator& a = streams_.at(stream);
  if (newest_ && stamp < *newest_ - options_.reorder_window) ++a.out_of_order;
  if (!newest_ || stamp > *newest_) newest_ = stamp;
  if (a.count == 0) {
    a.first = a.min = a.max = stamp;
  } else if (stamp < a.previous) {
    ++a.backwards;
  } else if (stamp == a.previous) {
    ++a.duplicates;
  } else {
    a.periods_s.push_back(static_cast<float>(ToSeconds(stamp - a.previous)));
  }
  a.min = std::min(a.min, stamp);
  a.max = std::max(a.max, stamp);
  a.previous = stamp;
  ++a.count;
}

StreamTimeReport StreamDiagnostics::Report(int stream) const {
  const Accumulator& a = streams_.at(stream);
  StreamTimeReport r;
  r.count = a.count;
  r.first = a.min;
  r.last = a.max;
  r.backwards = a.backwards;
  r.duplicates = a.duplicates;
  r.out_of_order = a.out_of_order;
  if (a.count > 1 && a.max > a.min) r.rate_hz = (a.count - 1) / ToSeconds(a.max - a.min);
  if (!a.periods_s.empty()) {
    // Gaps are periods far above the median; the jitter is the spread of the remaining ones.
    r.median_period_s = Median(a.periods_s);
    const double gap_threshold = options_.gap_factor * r.median_period_s;
    double sum = 0, sum_sq = 0;
    std::int64_t regular = 0;
    for (float p : a.periods_s) {
      if (p > gap_threshold) {
        ++r.gaps;
        r.largest_gap_s = std::max(r.largest_gap_s, double(p));
      } else {
        sum += p;
        sum_sq += double(p) * p;
        ++regular;
      }
    }
    const double mean = regular ? sum / regular : 0;
    const double variance = regular ? std::max(0.0, sum_sq / regular - mean * mean) : 0;
    r.jitter_percent = mean > 0 ? 100.0 * std::sqrt(variance) / mean : 0;
  }
  Judge(r, options_);
  return r;
}

}  // namespace uf
