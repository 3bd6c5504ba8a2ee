#include "viewer/pipeline/stage_runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace uf::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

std::string Seconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f s", seconds);
  return text;
}

std::string Items(const StageRecord& stage) {
  if (stage.status == StageStatus::kSkipped || stage.status == StageStatus::kNotRun) return "-";
  return std::to_string(stage.items) + " " + stage.unit;
}

std::string Outputs(const StageRecord& stage) {
  std::string list;
  for (const std::string& file : stage.outputs) list += (list.empty() ? "" : ", ") + file;
  return list.empty() ? "-" : list;
}

}  // namespace

std::string_view StageStatusName(StageStatus status) {
  switch (status) {
    case StageStatus::kOk:
      return "ok";
    case StageStatus::kFailed:
      return "failed";
    case StageStatus::kSkipped:
      return "skipped";
    case StageStatus::kNotRun:
      return "not run";
  }
  return "?";
}

void StageContext::Progress(std::int64_t done, std::int64_t total) {
  record_.items = done;
  progress_.Update(record_.name, done, total, record_.unit);
}

const StageRecord* FailedStage(const std::vector<StageRecord>& stages) {
  for (const StageRecord& stage : stages)
    if (stage.status == StageStatus::kFailed) return &stage;
  return nullptr;
}

const StageRecord* PipelineResult::failure() const { return FailedStage(stages); }

PipelineResult RunStages(const std::vector<Stage>& stages, ProgressLine& progress,
                         const std::string& command) {
  PipelineResult result;
  for (const Stage& stage : stages) {
    StageRecord record;
    record.name = stage.name;
    record.needs = stage.needs;
    result.stages.push_back(std::move(record));
  }
  const StageRecord* failed = nullptr;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    StageRecord& record = result.stages[i];
    if (failed) {
      record.message = "the " + failed->name + " stage failed";
      continue;
    }
    if (!stages[i].skip_reason.empty()) {
      record.status = StageStatus::kSkipped;
      record.message = stages[i].skip_reason;
      std::fprintf(stderr, "%s: %s skipped (%s)\n", command.c_str(), record.name.c_str(),
                   record.message.c_str());
      continue;
    }
    StageContext context(progress, record);
    progress.BeginStage(record.name);
    const Clock::time_point start = Clock::now();
    const Status status = stages[i].run(context);
    record.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    progress.EndLine();
    record.status = status.ok() ? StageStatus::kOk : StageStatus::kFailed;
    if (!status.ok()) {
      record.message = status.message();
      failed = &record;
    }
    std::fprintf(stderr, "%s: %s %s: %s in %s\n", command.c_str(), record.name.c_str(),
                 std::string(StageStatusName(record.status)).c_str(), Items(record).c_str(),
                 Seconds(record.seconds).c_str());
  }
  return result;
}

std::string FormatStageTable(const std::vector<StageRecord>& stages) {
  std::vector<std::vector<std::string>> rows = {{"stage", "status", "items", "time", "outputs"}};
  for (const StageRecord& s : stages)
    rows.push_back(
        {s.name, std::string(StageStatusName(s.status)), Items(s),
         s.status == StageStatus::kOk || s.status == StageStatus::kFailed ? Seconds(s.seconds) : "-",
         Outputs(s)});
  // Every column but the last padded to its widest cell.
  std::vector<std::size_t> width(rows[0].size(), 0);
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  std::string table;
  for (const auto& row : rows) {
    std::string line = " ";
    for (std::size_t c = 0; c < row.size(); ++c)
      line += " " + row[c] + (c + 1 < row.size() ? std::string(width[c] - row[c].size() + 1, ' ') : "");
    table += line + "\n";
  }
  return table;
}

std::string FormatStageMarkdown(const std::vector<StageRecord>& stages) {
  std::string md = "| stage | needs | status | items | time [s] | outputs |\n|---|---|---|---|---|---|\n";
  for (const StageRecord& s : stages) {
    char seconds[32] = "-";
    if (s.status == StageStatus::kOk || s.status == StageStatus::kFailed)
      std::snprintf(seconds, sizeof(seconds), "%.2f", s.seconds);
    md += "| " + s.name + " | " + s.needs + " | " + std::string(StageStatusName(s.status)) + " | " +
          Items(s) + " | " + seconds + " | " + Outputs(s) + " |\n";
  }
  for (const StageRecord& s : stages)
    if (!s.message.empty())
      md += "\n- " + s.name + " " + std::string(StageStatusName(s.status)) + ": " + s.message;
  if (md.back() != '\n') md += "\n";
  return md;
}

}  // namespace uf::pipeline
