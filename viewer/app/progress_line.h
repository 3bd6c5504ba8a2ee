// Progress of long work on stderr: on a terminal one line rewritten at most every half second
// ("sim: sensors 120/1200 (10%), 23.1/s, 47 s left"); otherwise (logs, CI) a plain line every 10 %.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace uf::app {

class ProgressLine {
 public:
  explicit ProgressLine(std::string command);
  ~ProgressLine();  // ends a rewritten line

  // `done` of `total` items of `stage`; a new stage restarts the rate estimate.
  void Update(const std::string& stage, std::int64_t done, std::int64_t total);

 private:
  using Clock = std::chrono::steady_clock;
  std::string command_, stage_;
  bool terminal_;
  bool open_line_ = false;
  int last_decile_ = -1;
  Clock::time_point stage_start_, last_print_;
};

}  // namespace uf::app
