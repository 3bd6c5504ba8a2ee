// report.md of `ultrafusion run`: whether the run succeeded (and which stage failed, why), the stages'
// table, what was run on what (dataset summary as `ultrafusion info` prints it, mode, resolved config),
// counts, the per-scan timing table and plot, the map's size, the splat metrics (with a held-out comparison
// image and the loss plot), warnings grouped by kind and, when the dataset has ground truth, the trajectory
// accuracy computed exactly as `ultrafusion eval GROUND_TRUTH trajectory.tum --align se3` does, with its
// plots. report.html (report_html.h) is made from it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "viewer/pipeline/stage_runner.h"
#include "viewer/pipeline/run_files.h"

namespace uf::app {

// The accuracy section: the eval table, the plots written, or why there is none.
struct GroundTruthCheck {
  bool evaluated = false;
  double ape_rmse_m = 0;
  std::size_t matched_poses = 0;   // estimated poses paired with the ground truth
  std::string table;               // as `ultrafusion eval` prints it
  std::vector<std::string> plots;  // paths relative to the output folder
  std::string note;                // "no ground truth in the dataset", or the evaluation's error
};

// Reads both trajectories, evaluates with eval's defaults (SE3 Umeyama alignment, max_dt 0.01 s, RPE over
// 1 frame) and writes the APE/RPE plots into out_folder/plots. Never fails: problems end up in `note`.
GroundTruthCheck EvaluateAgainstGroundTruth(const std::filesystem::path& ground_truth,
                                            const std::filesystem::path& out_folder,
                                            const std::string& estimate_file);

// The map stage: a one-line summary ("1.2 M points, 64 % coloured, ..."), the files it wrote, its warnings.
struct MapSummary {
  std::string summary, files;
  std::vector<std::string> warnings;
};

// The splat stages: metrics as (name, value) rows, a comparison image and the loss plot (paths relative to
// the output folder, "" when none), the views rendered.
struct SplatSummary {
  std::vector<std::pair<std::string, std::string>> metrics;
  std::string comparison, loss_plot;
  std::string views;  // "12 views in views/ (EXR + PNG)", once the views stage ran
};

struct RunReport {
  std::string dataset, format, mode, output_frame;
  std::vector<std::string> notes;  // mode fallbacks, no-op options
  std::string config_yaml;         // the resolved config, as saved in config.yaml
  std::int64_t scans = 0, keyframes = 0, skipped = 0;
  TimingSummary timing;
  double wall_seconds = 0;
  std::vector<ReadWarning> reader_warnings;
  std::vector<std::string> odometry_warnings;
  GroundTruthCheck accuracy;
  std::optional<MapSummary> map;      // none with --no-map
  std::optional<SplatSummary> splat;  // once the splat stage ran
  std::string dataset_summary;        // the dataset stage's table, as `ultrafusion info` prints it
  std::string timing_plot;            // "plots/timing_per_scan.png" once written
  std::string repeat_command;         // the command line that repeats the run with config.yaml
  std::vector<StageRecord> stages;
};

// Odometry warnings grouped by kind (the text before " ("), first example kept, in order of appearance.
std::vector<ReadWarning> GroupWarnings(const std::vector<std::string>& warnings);

std::string FormatRunReport(const RunReport& report);

// One number as printf_format gives it (e.g. "%.2f"), for the report's tables.
std::string FormatValue(const char* printf_format, double value);

}  // namespace uf::app
