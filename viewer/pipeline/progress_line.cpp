#include "viewer/pipeline/progress_line.h"

#include <unistd.h>

#include <cstdio>

namespace uf::pipeline {
namespace {

// The largest of 10, 20, 50, 100, 200, 500, ... that is <= done (0 below 10): the counts at which a line
// is printed off a terminal when the total is unknown.
std::int64_t OneTwoFiveMark(std::int64_t done) {
  std::int64_t mark = 0;
  for (std::int64_t decade = 10; decade <= done && decade > 0; decade *= 10)
    for (std::int64_t step : {1, 2, 5})
      if (step * decade <= done) mark = step * decade;
  return mark;
}

}  // namespace

ProgressLine::ProgressLine(std::string command)
    : command_(std::move(command)), terminal_(isatty(STDERR_FILENO)), stage_start_(Clock::now()) {}

ProgressLine::~ProgressLine() { EndLine(); }

void ProgressLine::EndLine() {
  if (open_line_) std::fprintf(stderr, "\n");
  open_line_ = false;
}

void ProgressLine::BeginStage(const std::string& stage) {
  stage_ = stage;
  stage_start_ = Clock::now();
  last_mark_ = -1;
}

void ProgressLine::Update(const std::string& stage, std::int64_t done, std::int64_t total,
                          const std::string& unit) {
  const Clock::time_point now = Clock::now();
  if (stage != stage_) {
    stage_ = stage;
    stage_start_ = now;
    last_mark_ = -1;
  }
  const bool known = total > 0;
  const double fraction = known ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
  const std::int64_t mark = known ? static_cast<std::int64_t>(fraction * 10.0) : OneTwoFiveMark(done);
  if (terminal_ ? (now - last_print_ < std::chrono::milliseconds(500) && !(known && done >= total))
                : mark == last_mark_)
    return;
  last_print_ = now;
  last_mark_ = mark;
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const std::string items = unit.empty() ? "" : " " + unit;
  if (known) {
    // Remaining time at the mean rate of the stage so far.
    const double left = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
    std::fprintf(stderr, "%s%s: %s %lld/%lld%s (%.0f%%), %.1f/s, %.0f s left%s", terminal_ ? "\r" : "",
                 command_.c_str(), stage.c_str(), static_cast<long long>(done), static_cast<long long>(total),
                 items.c_str(), 100.0 * fraction, rate, left, terminal_ ? "\033[K" : "\n");
  } else {
    std::fprintf(stderr, "%s%s: %s %lld%s, %.1f/s%s", terminal_ ? "\r" : "", command_.c_str(), stage.c_str(),
                 static_cast<long long>(done), items.c_str(), rate, terminal_ ? "\033[K" : "\n");
  }
  open_line_ = terminal_;
  std::fflush(stderr);
}

}  // namespace uf::pipeline
