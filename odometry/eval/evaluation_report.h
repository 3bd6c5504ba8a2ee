// Presenting an evaluation: console table, JSON file and PNG plots.
#pragma once

#include <ostream>
#include <string>

#include "odometry/eval/evaluation.h"

namespace uf {

struct EvalContext {
  std::string reference_path, estimate_path;
  std::size_t reference_poses, estimate_poses;
  std::size_t reference_duplicates = 0, estimate_duplicates = 0;  // poses skipped for repeating a stamp
  EvalOptions options;
  std::string align_name, rpe_unit_name;
};

void PrintEvalTable(std::ostream& out, const EvalContext& context, const EvalResult& result);
Status WriteEvalJson(const std::string& path, const EvalContext& context, const EvalResult& result);
// ape_top_view.png, ape_over_time.png and, when there are RPE pairs, rpe_over_time.png.
Status WriteEvalPlots(const std::string& folder, const EvalContext& context, const EvalResult& result);

}  // namespace uf
