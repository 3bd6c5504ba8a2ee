// Progress of long work on stderr: on a terminal one line rewritten at most every half second
// ("sim: sensors 120/1200 (10%), 23.1/s, 47 s left"); otherwise (logs, CI) a plain line every 10 %.
// When the total is not known in advance (total <= 0) the line shows the count and the rate only
// ("run: odometry 120 scans, 23.1/s"), and off a terminal a line is printed at 10, 20, 50, 100, 200, ...
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace uf::pipeline {

class ProgressLine {
 public:
  explicit ProgressLine(std::string command);
  ~ProgressLine();  // ends a rewritten line

  // `done` of `total` items of `stage` (total <= 0: unknown); a new stage restarts the rate estimate.
  // `unit` names the items ("scans"); empty: none shown.
  void Update(const std::string& stage, std::int64_t done, std::int64_t total, const std::string& unit = "");
  // Starts the clock of `stage` (the rate and remaining time count from here) without printing.
  void BeginStage(const std::string& stage);
  // Ends a rewritten line, so that the next output starts on a line of its own.
  void EndLine();

 private:
  using Clock = std::chrono::steady_clock;
  std::string command_, stage_;
  bool terminal_;
  bool open_line_ = false;
  std::int64_t last_mark_ = -1;  // the last 10 % step (known total) or 1-2-5 count (unknown) printed
  Clock::time_point stage_start_, last_print_;
};

}  // namespace uf::pipeline
