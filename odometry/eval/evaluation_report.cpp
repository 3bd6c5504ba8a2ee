#include "odometry/eval/evaluation_report.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "odometry/eval/plots.h"
#include "odometry/io/atomic_file.h"

namespace uf {
namespace {

std::string Row(const char* name, const ErrorStats& s) {
  char line[256];
  std::snprintf(line, sizeof(line), "%-18s %10.6f %10.6f %10.6f %10.6f %10.6f %10.6f %8zu\n", name, s.rmse,
                s.mean, s.median, s.std, s.min, s.max, s.n);
  return line;
}

nlohmann::json StatsJson(const ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std}, {"min", s.min},
          {"max", s.max},   {"n", s.n}};
}

std::string RpeLabel(const EvalContext& context) {
  char label[64];
  std::snprintf(label, sizeof(label), "RPE [m] (%g %s)", context.options.rpe_delta,
                context.rpe_unit_name.c_str());
  return label;
}

std::string DuplicatesNote(std::size_t duplicates) {
  return duplicates == 0 ? "" : ", " + std::to_string(duplicates) + " repeated stamps skipped";
}

}  // namespace

void PrintEvalTable(std::ostream& out, const EvalContext& context, const EvalResult& result) {
  const Similarity& a = result.alignment;
  out << "reference: " << context.reference_path << " (" << context.reference_poses << " poses"
      << DuplicatesNote(context.reference_duplicates) << ")\n"
      << "estimate:  " << context.estimate_path << " (" << context.estimate_poses << " poses"
      << DuplicatesNote(context.estimate_duplicates) << ")\n"
      << "matched:   " << result.association.size() << " pairs\n";
  char line[256];
  std::snprintf(line, sizeof(line), "alignment: %s, scale %.6f, rotation %.4f deg, translation %.4f m\n",
                context.align_name.c_str(), a.scale, a.rotation.angle() * 180.0 / std::numbers::pi,
                a.translation.norm());
  out << line;
  out << "\n                         rmse       mean     median        std        min        max        n\n";
  out << Row("APE [m]", result.ape);
  if (result.rpe)
    out << Row(RpeLabel(context).c_str(), *result.rpe);
  else
    out << RpeLabel(context) << ": no pose pair is that far apart\n";
  if (result.kitti_drift) {
    const KittiDrift& d = *result.kitti_drift;
    if (d.segments == 0)
      out << "KITTI drift: none (the reference path is shorter than 100 m)\n";
    else {
      std::snprintf(line, sizeof(line),
                    "KITTI drift: %.4f %% translation, %.4f deg/100 m rotation, path scale %+.1f ppm (%zu "
                    "segments)\n",
                    d.t_pct, d.r_deg_per_100m, d.scale_ppm, d.segments);
      out << line;
    }
  }
}

Status WriteEvalJson(const std::string& path, const EvalContext& context, const EvalResult& result) {
  const Similarity& a = result.alignment;
  nlohmann::json json = {
      {"reference", context.reference_path},
      {"estimate", context.estimate_path},
      {"reference_poses", context.reference_poses},
      {"estimate_poses", context.estimate_poses},
      {"skipped_duplicate_stamps",
       {{"reference", context.reference_duplicates}, {"estimate", context.estimate_duplicates}}},
      {"matched", result.association.size()},
      {"options",
       {{"max_dt", ToSeconds(context.options.max_dt)},
        {"t_offset", ToSeconds(context.options.estimate_offset)},
        {"align", context.align_name},
        {"rpe_delta", context.options.rpe_delta},
        {"rpe_unit", context.rpe_unit_name}}},
      {"alignment",
       {{"scale", a.scale},
        {"rotation", nlohmann::json::array()},
        {"translation", {a.translation.x(), a.translation.y(), a.translation.z()}}}},
      {"ape", StatsJson(result.ape)},
      {"rpe", result.rpe ? StatsJson(*result.rpe) : nlohmann::json(nullptr)},
  };
  for (int r = 0; r < 3; ++r)
    json["alignment"]["rotation"].push_back(
        {a.rotation.matrix()(r, 0), a.rotation.matrix()(r, 1), a.rotation.matrix()(r, 2)});
  if (result.kitti_drift) {
    const KittiDrift& d = *result.kitti_drift;
    const bool defined = d.segments > 0;
    json["kitti_drift"] = {
        {"t_pct", defined ? nlohmann::json(d.t_pct) : nlohmann::json(nullptr)},
        {"r_deg_per_100m", defined ? nlohmann::json(d.r_deg_per_100m) : nlohmann::json(nullptr)},
        {"scale_ppm", defined ? nlohmann::json(d.scale_ppm) : nlohmann::json(nullptr)},
        {"segments", d.segments}};
  }
  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  file.stream() << json.dump(2) << "\n";
  return file.Commit();
}

Status WriteEvalPlots(const std::string& folder, const EvalContext& context, const EvalResult& result) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) return Status::Error(folder + ": cannot create the plot folder: " + error.message());
  const std::vector<Eigen::Vector3d> reference = Positions(result.reference);
  const std::vector<Eigen::Vector3d> estimate = Positions(result.estimate);
  const std::string title = "APE (" + context.align_name + " aligned)";
  const std::string time_label = result.stamped ? "t [s]" : "pose index";
  if (Status s = WriteTopViewPlot(folder + "/ape_top_view.png", reference, estimate, result.ape_errors,
                                  title + ": top view", "APE [m]");
      !s.ok())
    return s;
  if (Status s = WriteErrorPlot(folder + "/ape_over_time.png", result.seconds, result.ape_errors, result.ape,
                                title, time_label, "APE [m]");
      !s.ok())
    return s;
  if (!result.rpe) return {};
  std::vector<double> rpe_seconds;
  for (const auto& pair : result.rpe_pairs) rpe_seconds.push_back(result.seconds[pair.second]);
  return WriteErrorPlot(folder + "/rpe_over_time.png", rpe_seconds, result.rpe_errors, *result.rpe,
                        RpeLabel(context), time_label, "RPE [m]");
}

}  // namespace uf
