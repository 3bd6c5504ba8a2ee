#include "viewer/app/report/run_report.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "odometry/eval/evaluation.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/io/warning_log.h"
#include "viewer/app/report/eval_report.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;

void AppendWarnings(std::string& md, const std::vector<ReadWarning>& warnings, const char* source) {
  for (const ReadWarning& w : warnings)
    md += "| " + std::string(source) + " | " + w.stream + " | " + w.what + " | " + std::to_string(w.count) +
          " |\n";
}

}  // namespace

GroundTruthCheck EvaluateAgainstGroundTruth(const fs::path& ground_truth, const fs::path& out_folder,
                                            const std::string& estimate_file) {
  GroundTruthCheck check;
  // The same steps and defaults as `ultrafusion eval REF EST --align se3` (eval_command.cpp).
  auto reference = ReadTrajectory(ground_truth.string());
  if (!reference) {
    check.note = "ground truth unreadable: " + reference.error();
    return check;
  }
  const std::string estimate_path = (out_folder / estimate_file).string();
  auto estimate = ReadTrajectory(estimate_path);
  if (!estimate) {
    check.note = "estimate unreadable: " + estimate.error();
    return check;
  }
  const EvalOptions options;  // align se3, max_dt 0.01 s, RPE delta 1 frame
  auto result = Evaluate(*reference, *estimate, options);
  if (!result) {
    check.note = "evaluation failed: " + result.error();
    return check;
  }
  const EvalContext context{.reference_path = ground_truth.string(),
                            .estimate_path = estimate_file,
                            .reference_poses = reference->size(),
                            .estimate_poses = estimate->size(),
                            .options = options,
                            .align_name = "se3",
                            .rpe_unit_name = "frames"};
  std::ostringstream table;
  PrintEvalTable(table, context, *result);
  check.table = table.str();
  check.evaluated = true;
  check.ape_rmse_m = result->ape.rmse;
  check.matched_poses = result->estimate.size();
  if (Status s = WriteEvalPlots((out_folder / "plots").string(), context, *result); !s.ok()) {
    check.note = "plots not written: " + s.message();
    return check;
  }
  for (const char* plot : {"ape_top_view.png", "ape_over_time.png", "rpe_over_time.png"})
    if (fs::exists(out_folder / "plots" / plot)) check.plots.push_back(std::string("plots/") + plot);
  return check;
}

std::vector<ReadWarning> GroupWarnings(const std::vector<std::string>& warnings) {
  WarningLog log;
  for (const std::string& warning : warnings) log.Add("odometry", warning);
  return log.entries();
}

std::string FormatValue(const char* printf_format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), printf_format, value);
  return text;
}

std::string FormatRunReport(const RunReport& r) {
  std::string md = "# ultrafusion run\n\n";
  const auto failed = std::find_if(r.stages.begin(), r.stages.end(),
                                   [](const StageRecord& s) { return s.status == StageStatus::kFailed; });
  if (failed != r.stages.end())
    md += "**Run failed** in the " + failed->name + " stage: " + failed->message +
          "\n\nThe outputs of the stages before it are kept; the later stages did not run.\n\n";
  md += "- dataset: `" + r.dataset + "` (" + r.format + ")\n";
  md += "- mode: " + r.mode + "\n";
  md += "- output frame: " + r.output_frame + "\n";
  for (const std::string& note : r.notes) md += "- note: " + note + "\n";
  if (!r.stages.empty()) md += "\n## Stages\n\n" + FormatStageMarkdown(r.stages);
  if (!r.dataset_summary.empty())
    md += "\n## Dataset (as `ultrafusion info` prints it)\n\n```\n" + r.dataset_summary + "```\n";
  md += "\n## Counts\n\n| item | count |\n|---|---|\n";
  md += "| LiDAR scans fed | " + std::to_string(r.scans) + " |\n";
  md += "| keyframes (trajectory poses) | " + std::to_string(r.keyframes) + " |\n";
  md += "| scans skipped by the odometry | " + std::to_string(r.skipped) + " |\n";
  md += "| wall time [s] | " + FormatValue("%.2f", r.wall_seconds) + " |\n";
  md += "\n## Timing per scan (AddScan + TakeFinished, wall time)\n\n";
  md += "| mean [ms] | median [ms] | p95 [ms] | max [ms] |\n|---|---|---|---|\n";
  md += "| " + FormatValue("%.2f", r.timing.mean) + " | " + FormatValue("%.2f", r.timing.median) + " | " +
        FormatValue("%.2f", r.timing.p95) + " | " + FormatValue("%.2f", r.timing.max) + " |\n";
  if (!r.timing_plot.empty()) md += "\n![time per scan](" + r.timing_plot + ")\n";
  if (r.map) md += "\n## Map\n\n" + r.map->summary + "\n\nFiles: " + r.map->files + "\n";
  if (r.splat) {
    md += "\n## Splats\n\n| metric | value |\n|---|---|\n";
    for (const auto& [name, value] : r.splat->metrics) md += "| " + name + " | " + value + " |\n";
    if (!r.splat->views.empty()) md += "\n" + r.splat->views + "\n";
    if (!r.splat->comparison.empty())
      md += "\nA held-out image (left) and the splats rendered at its pose (right):\n\n![held-out view](" +
            r.splat->comparison + ")\n";
    if (!r.splat->loss_plot.empty()) md += "\n![splat training loss](" + r.splat->loss_plot + ")\n";
  }
  md += "\n## Accuracy\n\n";
  if (r.accuracy.evaluated) {
    md += "ATE (APE translation RMSE, SE3-aligned): " + FormatValue("%.4f", r.accuracy.ape_rmse_m) + " m\n\n";
    md += "As `ultrafusion eval GROUND_TRUTH trajectory.tum --align se3` reports it:\n\n```\n" +
          r.accuracy.table + "```\n\n";
    for (const std::string& plot : r.accuracy.plots) md += "![" + plot + "](" + plot + ")\n";
  }
  if (!r.accuracy.note.empty()) md += r.accuracy.note + "\n";
  md += "\n## Warnings\n\n";
  const std::vector<ReadWarning> odometry = GroupWarnings(r.odometry_warnings);
  const std::vector<ReadWarning> map = r.map ? GroupWarnings(r.map->warnings) : std::vector<ReadWarning>{};
  if (r.reader_warnings.empty() && odometry.empty() && map.empty()) {
    md += "none\n";
  } else {
    md += "| source | stream | what (first occurrence) | count |\n|---|---|---|---|\n";
    AppendWarnings(md, r.reader_warnings, "reader");
    AppendWarnings(md, odometry, "odometry");
    AppendWarnings(md, map, "map");
  }
  md += "\n## Configuration (config.yaml)\n\n";
  if (!r.repeat_command.empty()) md += "Repeat the run with `" + r.repeat_command + "`\n\n";
  md += "```yaml\n" + r.config_yaml + "```\n";
  return md;
}

}  // namespace uf::app
