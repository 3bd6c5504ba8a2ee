// A staged pipeline, as `ultrafusion run` uses it: named stages run in order, each timed, each reporting
// its progress (items done, rate, remaining time) and the files it wrote. A stage that fails stops the
// pipeline: the stages after it are not run, and what the earlier ones wrote stays. Adding a stage is
// one entry in the list: a name, what it needs, an optional reason to skip it, and the function.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/types/status.h"
#include "viewer/pipeline/progress_line.h"

namespace uf::pipeline {

enum class StageStatus { kOk, kFailed, kSkipped, kNotRun };

// "ok", "failed", "skipped", "not run".
std::string_view StageStatusName(StageStatus status);

// What a stage knows of itself while it runs and after: filled by the stage through StageContext.
struct StageRecord {
  std::string name, needs;
  StageStatus status = StageStatus::kNotRun;
  std::int64_t items = 0;
  std::string unit = "items";        // what the items are: "scans", "keyframes", "files"
  double seconds = 0;                // wall time of the stage
  std::vector<std::string> outputs;  // files written, relative to the output folder
  std::string message;  // failed: the error; skipped: why; not run: which stage failed; ok: a remark
};

// Handed to a running stage: progress and outputs go through it.
class StageContext {
 public:
  StageContext(ProgressLine& progress, StageRecord& record) : progress_(progress), record_(record) {}

  // `done` items of `total` (total <= 0: unknown); shown on stderr and kept as the stage's item count.
  void Progress(std::int64_t done, std::int64_t total = 0);
  void SetUnit(std::string unit) { record_.unit = std::move(unit); }
  // A file the stage wrote, relative to the output folder.
  void AddOutput(std::string file) { record_.outputs.push_back(std::move(file)); }
  // A remark for the report's stage list, for a stage that succeeded with a reservation.
  void SetMessage(std::string message) { record_.message = std::move(message); }

 private:
  ProgressLine& progress_;
  StageRecord& record_;
};

struct Stage {
  std::string name;         // "odometry"
  std::string needs;        // what it reads: "dataset (LiDAR, IMU)"
  std::string skip_reason;  // not empty: the stage is skipped, this says why ("--no-map")
  std::function<Status(StageContext&)> run;
};

// The stage that failed, or nullptr.
const StageRecord* FailedStage(const std::vector<StageRecord>& stages);

struct PipelineResult {
  std::vector<StageRecord> stages;  // one per stage, in order
  // The stage that failed, or nullptr.
  const StageRecord* failure() const;
};

// Runs the stages in order until one fails. Each stage's start and end are announced on stderr
// ("run: odometry ok: 40 scans in 3.1 s"); `command` prefixes the lines.
PipelineResult RunStages(const std::vector<Stage>& stages, ProgressLine& progress,
                         const std::string& command);

// The summary table for the console: one aligned row per stage (stage, status, items, time, outputs).
std::string FormatStageTable(const std::vector<StageRecord>& stages);

// The same table in Markdown, with the failure's and the skips' reasons.
std::string FormatStageMarkdown(const std::vector<StageRecord>& stages);

}  // namespace uf::pipeline
