// report.md of `ultrafusion run`: whether the run succeeded (and which stage failed, why), the stages'
// table, what was run on what (dataset summary as `ultrafusion info` prints it, mode, resolved config),
// counts, the per-scan timing table and plot, the map's size, the splat metrics (with a held-out comparison
// image and the loss plot), warnings grouped by kind and, when the dataset has ground truth, the trajectory
// accuracy computed exactly as `ultrafusion eval GROUND_TRUTH trajectory.tum --align se3` does, with its
// plots. Everything comes from the run's pipeline::RunSummary; report.html (report_html.h) is made from the
// Markdown.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "viewer/pipeline/run/run_summary.h"

namespace uf::app {

// Odometry warnings grouped by kind (the text before " ("), first example kept, in order of appearance.
std::vector<ReadWarning> GroupWarnings(const std::vector<std::string>& warnings);

std::string FormatRunReport(const pipeline::RunSummary& summary);

// report.md and report.html (report_html.h) in `out`, each written atomically.
Status WriteRunReports(const std::filesystem::path& out, const pipeline::RunSummary& summary);

// One number as printf_format gives it (e.g. "%.2f"), for the report's tables.
std::string FormatValue(const char* printf_format, double value);

}  // namespace uf::app
