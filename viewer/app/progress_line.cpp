#include "viewer/app/progress_line.h"

#include <unistd.h>

#include <cstdio>

namespace uf::app {

ProgressLine::ProgressLine(std::string command)
    : command_(std::move(command)), terminal_(isatty(STDERR_FILENO)), stage_start_(Clock::now()) {}

ProgressLine::~ProgressLine() {
  if (open_line_) std::fprintf(stderr, "\n");
}

void ProgressLine::Update(const std::string& stage, std::int64_t done, std::int64_t total) {
  const Clock::time_point now = Clock::now();
  if (stage != stage_) {
    stage_ = stage;
    stage_start_ = now;
    last_decile_ = -1;
  }
  const double fraction = total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
  const int decile = static_cast<int>(fraction * 10.0);
  if (terminal_ ? (now - last_print_ < std::chrono::milliseconds(500) && done < total)
                : decile == last_decile_)
    return;
  last_print_ = now;
  last_decile_ = decile;
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double left = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
  std::fprintf(stderr, "%s%s: %s %lld/%lld (%.0f%%), %.1f/s, %.0f s left%s", terminal_ ? "\r" : "",
               command_.c_str(), stage.c_str(), static_cast<long long>(done), static_cast<long long>(total),
               100.0 * fraction, rate, left, terminal_ ? "\033[K" : "\n");
  open_line_ = terminal_;
  std::fflush(stderr);
}

}  // namespace uf::app
