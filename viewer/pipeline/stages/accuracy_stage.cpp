#include "viewer/pipeline/stages/accuracy_stage.h"

#include <sstream>

#include "odometry/io/trajectory_file.h"

namespace uf::pipeline {

namespace fs = std::filesystem;

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

GroundTruthCheck RunAccuracyStage(const fs::path& ground_truth, const fs::path& out, StageContext& context) {
  context.SetUnit("poses");
  GroundTruthCheck accuracy = EvaluateAgainstGroundTruth(ground_truth, out, "trajectory.tum");
  if (!accuracy.evaluated) {
    context.SetMessage("not evaluated: " + accuracy.note);
    return accuracy;
  }
  // The poses evaluated (with --from, the odometry stage did not run here: its keyframe count is 0).
  const auto poses = static_cast<std::int64_t>(accuracy.matched_poses);
  context.Progress(poses, poses);
  for (const std::string& plot : accuracy.plots) context.AddOutput(plot);
  return accuracy;
}

}  // namespace uf::pipeline
