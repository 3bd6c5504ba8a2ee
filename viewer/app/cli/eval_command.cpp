#include "viewer/app/cli/eval_command.h"

#include <cmath>
#include <iostream>
#include <memory>

#include "odometry/eval/evaluation.h"
#include "odometry/eval/evaluation_report.h"
#include "odometry/io/trajectory_file.h"
#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/cli/subcommand.h"

namespace uf::app {
namespace {

struct EvalArguments {
  std::string reference_path, estimate_path;
  std::string reference_format = "auto", estimate_format = "auto";
  std::string reference_times, estimate_times;
  double max_dt = 0.01, t_offset = 0.0;
  std::string align = "se3";
  double rpe_delta = 1;
  std::string rpe_unit = "frames";
  bool kitti_drift = false;
  bool strict_stamps = false;
  std::string json_path, plot_dir;
};

// A pose repeating the previous stamp is skipped (the first pose of the stamp is kept, as evo does) and
// counted in *skipped_duplicates; with strict_stamps it is an error. Stamps going backwards are always an
// error.
Expected<Trajectory> LoadTrajectory(const std::string& path, const std::string& format_name,
                                    const std::string& times_path, bool strict_stamps,
                                    std::size_t* skipped_duplicates) {
  auto format = ParseTrajectoryFormat(format_name);
  if (!format) return format.status();
  TrajectoryReadReport report;
  auto trajectory = ReadTrajectory(path, *format, {.skip_duplicate_stamps = !strict_stamps}, &report);
  if (!trajectory) return trajectory.status();
  *skipped_duplicates = report.skipped_duplicates;
  if (report.skipped_duplicates > 0)
    std::cerr << "ultrafusion: warning: " << path << ": skipped " << report.skipped_duplicates
              << " poses repeating the previous stamp, kept the first of each (first skipped on line "
              << report.first_skipped_line << "; --strict-stamps makes this an error)\n";
  if (!times_path.empty()) {
    if (trajectory->has_stamps())
      return Status::Error(times_path + ": a times file is only for stampless (KITTI) trajectories; " + path +
                           " has stamps");
    auto stamps = ReadTimesFile(times_path);
    if (!stamps) return stamps.status();
    if (Status s = AttachStamps(*trajectory, std::move(*stamps), times_path); !s.ok()) return s;
  }
  return trajectory;
}

Expected<EvalOptions> ToOptions(const EvalArguments& a) {
  EvalOptions options;
  if (!std::isfinite(a.max_dt) || a.max_dt < 0 || a.max_dt > 1e6)
    return Status::Error("--max-dt must be a time in seconds >= 0, got " + std::to_string(a.max_dt));
  if (!std::isfinite(a.t_offset) || std::abs(a.t_offset) > 1e9)
    return Status::Error("--t-offset must be a finite time in seconds, got " + std::to_string(a.t_offset));
  options.max_dt = FromSeconds(a.max_dt);
  options.estimate_offset = FromSeconds(a.t_offset);
  options.align = a.align == "none"   ? AlignMode::kNone
                  : a.align == "sim3" ? AlignMode::kSim3
                  : a.align == "yaw"  ? AlignMode::kYaw
                                      : AlignMode::kSe3;
  options.rpe_unit = a.rpe_unit == "m" ? RpeUnit::kMetres : RpeUnit::kFrames;
  options.rpe_delta = a.rpe_delta;
  const bool whole = a.rpe_delta == std::floor(a.rpe_delta);
  if (!std::isfinite(a.rpe_delta) || a.rpe_delta <= 0 || (options.rpe_unit == RpeUnit::kFrames && !whole))
    return Status::Error("--rpe-delta must be > 0 (a whole number of frames with --rpe-unit frames), got " +
                         std::to_string(a.rpe_delta));
  options.kitti_drift = a.kitti_drift;
  return options;
}

int RunEval(const EvalArguments& arguments) {
  auto options = ToOptions(arguments);
  if (!options) {
    std::cerr << "ultrafusion eval: " << options.error() << "\n";
    return kExitUsage;
  }
  std::size_t reference_duplicates = 0, estimate_duplicates = 0;
  auto reference = LoadTrajectory(arguments.reference_path, arguments.reference_format,
                                  arguments.reference_times, arguments.strict_stamps, &reference_duplicates);
  if (!reference) return ReportError(reference.status());
  auto estimate = LoadTrajectory(arguments.estimate_path, arguments.estimate_format, arguments.estimate_times,
                                 arguments.strict_stamps, &estimate_duplicates);
  if (!estimate) return ReportError(estimate.status());

  auto result = Evaluate(*reference, *estimate, *options);
  if (!result) return ReportError(result.status());

  const EvalContext context{.reference_path = arguments.reference_path,
                            .estimate_path = arguments.estimate_path,
                            .reference_poses = reference->size(),
                            .estimate_poses = estimate->size(),
                            .reference_duplicates = reference_duplicates,
                            .estimate_duplicates = estimate_duplicates,
                            .options = *options,
                            .align_name = arguments.align,
                            .rpe_unit_name = arguments.rpe_unit};
  PrintEvalTable(std::cout, context, *result);
  if (!arguments.json_path.empty())
    if (Status s = WriteEvalJson(arguments.json_path, context, *result); !s.ok()) return ReportError(s);
  if (!arguments.plot_dir.empty())
    if (Status s = WriteEvalPlots(arguments.plot_dir, context, *result); !s.ok()) return ReportError(s);
  return kExitOk;
}

}  // namespace

Subcommand AddEvalCommand(CLI::App& app) {
  auto arguments = std::make_shared<EvalArguments>();
  CLI::App* eval =
      app.add_subcommand("eval", "Trajectory accuracy against a reference (evo-compatible APE/RPE)");
  eval->add_option("REFERENCE", arguments->reference_path, "Reference (ground-truth) trajectory file")
      ->required();
  eval->add_option("ESTIMATE", arguments->estimate_path, "Estimated trajectory file")->required();
  const auto formats = CLI::IsMember({"auto", "tum", "kitti", "euroc"});
  eval->add_option("--ref-format", arguments->reference_format, "Format of REFERENCE")
      ->check(formats)
      ->capture_default_str();
  eval->add_option("--est-format", arguments->estimate_format, "Format of ESTIMATE")
      ->check(formats)
      ->capture_default_str();
  eval->add_option("--ref-times", arguments->reference_times,
                   "Times file (s per line) for a KITTI REFERENCE");
  eval->add_option("--est-times", arguments->estimate_times, "Times file (s per line) for a KITTI ESTIMATE");
  eval->add_option("--max-dt", arguments->max_dt, "Largest |dt| [s] for associating stamps")
      ->capture_default_str();
  eval->add_option("--t-offset", arguments->t_offset, "Offset [s] added to the estimate's stamps")
      ->capture_default_str();
  eval->add_option(
          "--align", arguments->align,
          "Alignment of the estimate onto the reference (Umeyama; yaw: about z and a translation only, "
          "for gravity-aligned estimates, where a tilt counts as error)")
      ->check(CLI::IsMember({"se3", "sim3", "yaw", "none"}))
      ->capture_default_str();
  eval->add_option("--rpe-delta", arguments->rpe_delta, "RPE pair spacing")->capture_default_str();
  eval->add_option("--rpe-unit", arguments->rpe_unit, "Unit of --rpe-delta")
      ->check(CLI::IsMember({"frames", "m"}))
      ->capture_default_str();
  eval->add_flag("--kitti-drift", arguments->kitti_drift, "KITTI drift over 100..800 m segments");
  eval->add_flag(
      "--strict-stamps", arguments->strict_stamps,
      "A repeated stamp is an error (default: a counted warning that keeps the first pose, as evo)");
  eval->add_option("--json", arguments->json_path, "Write every figure to this JSON file");
  eval->add_option("--plot", arguments->plot_dir, "Write PNG plots into this folder");
  return {eval, [arguments] { return RunEval(*arguments); }};
}

}  // namespace uf::app
