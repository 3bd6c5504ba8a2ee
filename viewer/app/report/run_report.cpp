#include "viewer/app/report/run_report.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <tuple>

#include "odometry/io/warning_log.h"
#include "viewer/app/report/info_report.h"
#include "viewer/app/report/report_html.h"
#include "viewer/pipeline/run_files.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;

void AppendWarnings(std::string& md, const std::vector<ReadWarning>& warnings, const char* source) {
  for (const ReadWarning& w : warnings)
    md += "| " + std::string(source) + " | " + w.stream + " | " + w.what + " | " + std::to_string(w.count) +
          " |\n";
}

// The splat section: metrics as (name, value) rows, a comparison image and the loss plot (paths relative to
// the output folder, "" when none).
struct SplatSummary {
  std::vector<std::pair<std::string, std::string>> metrics;
  std::string comparison, loss_plot;
};

SplatSummary Summarize(const pipeline::SplatJobResult& result) {
  const pipeline::SplatMetrics& m = result.metrics;
  SplatSummary summary;
  summary.metrics = {
      {"held-out PSNR [dB] (psnr_test)", FormatValue("%.2f", m.test.psnr)},
      {"held-out SSIM (ssim_test)", FormatValue("%.3f", m.test.ssim)},
      {"held-out PSNR of the seeded model [dB]", FormatValue("%.2f", m.psnr_test_initial)},
      {"training PSNR [dB] (psnr_train)", FormatValue("%.2f", m.train.psnr)},
      {"views: training / held out", std::to_string(m.views_train) + " / " + std::to_string(m.views_test)},
      {"iterations", std::to_string(m.iterations) + " of " + std::to_string(m.iterations_planned) +
                         (m.stopped_by_time ? " (time budget reached)" : "")},
      {"iterations per second", FormatValue("%.2f", m.iterations_per_s())},
      {"Gaussians: seeded -> trained",
       std::to_string(m.gaussians_initial) + " -> " + std::to_string(m.gaussians)},
      {"seeds: map points / triangulated corners / sky", std::to_string(m.map_seeds) + " / " +
                                                             std::to_string(m.feature_seeds) + " / " +
                                                             std::to_string(m.sky_gaussians)},
      {"resolution [px]", std::to_string(m.width) + " x " + std::to_string(m.height)},
      {"device", m.device},
      {"camera", m.camera + " (" + std::to_string(m.images) + " images)"}};
  for (const std::string& file : result.files) {
    if (summary.comparison.empty() && file.ends_with("_compare.png")) summary.comparison = file;
    if (file == "plots/splat_loss.png") summary.loss_plot = file;
  }
  return summary;
}

// The tracking section: how many scans were rejected, registered from a fallback guess, or restarted the
// local map, and each event with its stamp (the first kMaxListed).
// run --calibrate-online: the estimates, what the run applied, the files.
std::string FormatOnlineCalibration(const pipeline::OnlineCalibrationSummary& applied,
                                    const pipeline::CalibrateResult& r) {
  std::string md = "\n## Online calibration (--calibrate-online)\n\n";
  md += "A LiDAR-only branch fed the calibration workers with " + std::to_string(applied.branch_scans) +
        " scans (docs/METHOD.md, \"Online spatiotemporal calibration\"); the window waited " +
        FormatValue("%.1f", applied.held_s) + " s of data for the locks (--calibration-hold).\n\n";
  if (r.time_offset_s)
    md += "- time offset: " + std::string(r.time_offset_locked ? "locked" : "not locked") + ", " +
          FormatValue("%+.4f", *r.time_offset_s) + " s on top of the offset read (" +
          FormatValue("%+.4f", ToSeconds(r.lidar_offset_read - r.imu_offset_read)) + " s)\n";
  else
    md += "- time offset: no estimate\n";
  if (applied.offset_applied_from)
    md += "- applied: " + FormatValue("%+.4f", applied.offset_applied_s) + " s added to the scans from " +
          FormatSeconds(*applied.offset_applied_from) + " on and to the poses before (" +
          std::to_string(applied.scans_left_out) +
          " re-stamped scans left out: they came before the previous scan)\n";
  else
    md += "- applied: nothing (the offset never locked); the run kept the given offset\n";
  if (r.R_imu_lidar) {
    const std::string angle = FormatValue("%.3f", r.RotationFromGivenDeg());
    md += "- rotation: " + std::string(r.rotation_locked ? "locked" : "not locked") + ", " + angle +
          " deg from the given one" +
          (r.rotation_locked
               ? std::string()
               : ", standard deviation " + FormatValue("%.3f", r.LatestRotationSigmaDeg()) + " deg (" +
                     (r.UsesEstimatedRotation() ? "written" : "the given one written") + ")") +
          "\n";
    md += applied.rotation_applied_at
              ? "- applied: " + angle + " deg of rotation from the scan at " +
                    FormatSeconds(*applied.rotation_applied_at) +
                    " on (the window's states and the poses before moved to it, their LiDAR poses kept)\n"
          : !applied.rotation_refused.empty()
              ? "- applied: nothing (" + applied.rotation_refused + "); the run kept the given rotation\n"
              : "- applied: nothing (the rotation never locked); the run kept the given rotation\n";
  } else {
    md += "- rotation: no estimate\n";
  }
  for (const auto& [worker, name, locked] :
       {std::tuple{estimator::CalibrationWorker::kTimeOffset, "time offset", r.time_offset_locked},
        std::tuple{estimator::CalibrationWorker::kRotation, "rotation", r.rotation_locked}}) {
    const std::string reason = r.LastRefusal(worker);
    if (!locked && !reason.empty()) md += std::string("- ") + name + ", last refused solve: " + reason + "\n";
  }
  md += "\nEvery solve: `calibration_solves.csv`; the estimates: `calibration_estimated.yaml`.\n";
  return md;
}

std::string FormatTracking(const std::vector<estimator::TrackEvent>& events, std::int64_t scans) {
  constexpr std::size_t kMaxListed = 100;
  using Kind = estimator::TrackEvent::Kind;
  const auto count = [&](Kind kind) {
    return std::to_string(std::count_if(events.begin(), events.end(),
                                        [&](const estimator::TrackEvent& e) { return e.kind == kind; }));
  };
  std::string md = "\n## Tracking\n\n";
  if (events.empty())
    return md + "Every one of the " + std::to_string(scans) +
           " scans was registered from its first guess: no rejection, no restart.\n";
  md += count(Kind::kRejected) + " scans rejected (predicted pose kept, not mapped), " +
        count(Kind::kFallbackGuess) + " registered from a fallback guess, " + count(Kind::kRestarted) +
        " restarts of the local map (the trajectory is discontinuous there):\n\n| stamp [s] | event | detail "
        "|\n|---|---|---|\n";
  for (std::size_t i = 0; i < events.size() && i < kMaxListed; ++i)
    md += "| " + FormatSeconds(events[i].stamp) + " | " +
          std::string(estimator::TrackEventName(events[i].kind)) + " | " + events[i].detail + " |\n";
  if (events.size() > kMaxListed)
    md += "\n(" + std::to_string(events.size() - kMaxListed) + " more events not listed)\n";
  return md;
}

// Spans of a reliability score as a table (the first 50): from, to, how many `unit`, the worst D.
std::string FormatSpans(const std::vector<pipeline::DegenerateSpan>& spans, const std::string& unit) {
  constexpr std::size_t kMaxListed = 50;
  if (spans.empty()) return "";
  std::string md = "\n| from [s] | to [s] | " + unit + " | worst D |\n|---|---|---|---|\n";
  for (std::size_t i = 0; i < spans.size() && i < kMaxListed; ++i) {
    const pipeline::DegenerateSpan& span = spans[i];
    md += "| " + FormatSeconds(span.first) + " | " + FormatSeconds(span.last) + " | " +
          std::to_string(span.keyframes) + " | " + FormatValue("%.2f", span.worst) + " |\n";
  }
  if (spans.size() > kMaxListed)
    md += "\n(" + std::to_string(spans.size() - kMaxListed) + " more spans not listed)\n";
  return md;
}

// "<n><what>." with n the items inside the spans, then the spans' table when there are any.
std::string CountAndSpans(const std::vector<pipeline::DegenerateSpan>& spans, const std::string& what,
                          const std::string& unit) {
  int inside = 0;
  for (const pipeline::DegenerateSpan& span : spans) inside += span.keyframes;
  return std::to_string(inside) + what + (spans.empty() ? ".\n" : ":\n") + FormatSpans(spans, unit);
}

// The plot, when it was written.
std::string PlotLink(const std::string& alt, const std::string& plot) {
  return plot.empty() ? "" : "\n![" + alt + "](" + plot + ")\n";
}

// The LiDAR's degeneracy scores (reliability.csv): how many keyframes were degenerate and where.
std::string FormatReliability(const pipeline::OdometrySummary& o) {
  std::string md = "\n## Reliability (LiDAR degeneracy)\n\n";
  md +=
      "Per keyframe, the score D of its registration's point-to-plane information (0: every direction "
      "pinned, 1: one left free; docs/METHOD.md \"Factor-wise reliability scheduling\"), in "
      "`reliability.csv` with its inputs. No factor is scheduled by the score (lo.drop_weak_directions, off "
      "by default, acts on the same information).\n\n";
  md += CountAndSpans(o.lidar_degenerate,
                      " of " + std::to_string(o.lidar_scored) +
                          " scored keyframes at D >= " + FormatValue("%.1f", pipeline::kDegenerateReported),
                      "keyframes");
  return md + PlotLink("LiDAR degeneracy", o.reliability_plot);
}

// With wheel scheduling: where the wheel's factors were left out.
std::string FormatWheelReliability(const pipeline::OdometrySummary& o) {
  std::string md = "\n## Reliability (wheel)\n\n";
  md +=
      "Per node interval, the score D of the wheel's motion against the IMU's prediction (0: they agree; "
      "docs/METHOD.md \"Factor-wise reliability scheduling\"), in `reliability.csv` with its inputs; the "
      "interval's wheel factor is left out while the gate is shut (slip, wheels off the ground).\n\n";
  md += CountAndSpans(o.wheel_suppressed,
                      " of " + std::to_string(o.wheel_scored) + " scored intervals left out", "intervals");
  return md + PlotLink("Wheel reliability", o.wheel_reliability_plot);
}

// The GNSS fixes' scores: how many, their mean, how many the innovation test rejected.
std::string FormatGnssReliability(const pipeline::OdometrySummary& o) {
  std::string md = "\n## Reliability (GNSS)\n\n";
  md +=
      "Per fix the innovation test saw, the score D of its status, covariance and innovation (0: RTK "
      "fixed where predicted; docs/METHOD.md \"Factor-wise reliability scheduling\"), in `reliability.csv`; "
      "the fix's factor is admitted by the innovation test and its step guard. " +
      std::to_string(o.gnss_scored) + " fixes scored, mean D " + FormatValue("%.2f", o.gnss_mean_score) +
      ", " + std::to_string(o.gnss_rejected) + " rejected.\n";
  return md + PlotLink("GNSS reliability", o.gnss_reliability_plot);
}

// With an IMU: its mean score and where it clipped.
std::string FormatImuReliability(const pipeline::OdometrySummary& o) {
  std::string md = "\n## Reliability (IMU)\n\n";
  md +=
      "Per node interval, the score D of the IMU's excitation, preintegration residual and clipped readings "
      "(docs/METHOD.md \"Factor-wise reliability scheduling\"), in `reliability.csv` with its inputs. "
      "Readings at the full scale (`imu.gyro_range`, `imu.accel_range`) loosen their interval's IMU factor, "
      "and the wheel is not scored against that interval. " +
      std::to_string(o.imu_scored) + " intervals scored, mean D " + FormatValue("%.2f", o.imu_mean_score) +
      ". ";
  md += CountAndSpans(o.imu_clipped, " with clipped readings", "intervals");
  return md + PlotLink("IMU reliability", o.imu_reliability_plot);
}

// With an IMU: the inertial window's velocities and biases (imu_states.csv) and the bias plots; the LiDAR
// translation's plot where the window estimated it.
std::string FormatImuStates(const pipeline::OdometrySummary& o) {
  std::string md = "\n## Inertial states\n\n";
  md += "The velocity and the IMU biases of the " + std::to_string(o.imu_states) +
        " keyframes the inertial window estimated, in `imu_states.csv` (the velocity in the estimator's "
        "world, the biases in the IMU frame).\n";
  md += PlotLink("Accelerometer bias", o.imu_accel_bias_plot) +
        PlotLink("Gyroscope bias", o.imu_gyro_bias_plot);
  if (o.lidar_translation_plot.empty()) return md;
  return md +
         "\nThe LiDAR extrinsic's translation as the window estimated it (`lio.estimate_lidar_translation`; "
         "its columns in `imu_states.csv`):\n" +
         PlotLink("LiDAR extrinsic translation", o.lidar_translation_plot);
}

// With the camera: where its frames were left out.
std::string FormatCameraReliability(const pipeline::OdometrySummary& o) {
  std::string md = "\n## Reliability (camera)\n\n";
  md +=
      "Per frame, the score D of its tracks held against the window's predicted motion (agreeing tracks, "
      "their grid occupancy, the median disagreement; docs/METHOD.md \"Factor-wise reliability "
      "scheduling\"), in `reliability.csv` with its inputs. With `visual.schedule.enabled` (off by "
      "default) a frame's observations are left out while the gate is shut (an object crossing the view, "
      "frames with too few tracks).\n\n";
  md += CountAndSpans(o.camera_suppressed,
                      " of " + std::to_string(o.camera_scored) + " checked frames left out", "frames");
  return md + PlotLink("Camera reliability", o.camera_reliability_plot);
}

// V modes: the camera's landmarks per step (node or scan) and their reprojection error.
std::string FormatVisual(const pipeline::OdometrySummary::Visual& v, const std::string& step) {
  std::string md = "\n## Camera in the window\n\n";
  md += "Landmarks per " + step + " after its solve: mean " + FormatValue("%.1f", v.mean_landmarks) +
        ", fewest " + std::to_string(v.fewest_landmarks) + " over the " +
        std::to_string(v.steps_with_landmarks) + " " + step +
        "s that had any; mean reprojection error there " + FormatValue("%.3f", v.mean_reprojection_px) +
        " px. Per frame: `tracks.csv`.\n";
  md += "\n![landmarks per " + step + "](" + v.plot + ")\n";
  return md;
}

}  // namespace

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

std::string FormatRunReport(const pipeline::RunSummary& r) {
  std::string md = "# ultrafusion run\n\n";
  if (const pipeline::StageRecord* failed = pipeline::FailedStage(r.stages))
    md += "**Run failed** in the " + failed->name + " stage: " + failed->message +
          "\n\nThe outputs of the stages before it are kept; the later stages did not run.\n\n";
  md += "- dataset: `" + r.dataset + "` (" + r.format + ")\n";
  md += "- mode: " + r.mode + "\n";
  md += "- output frame: " + std::string(pipeline::Name(r.output_frame)) + "\n";
  for (const std::string& note : r.notes) md += "- note: " + note + "\n";
  if (!r.stages.empty()) md += "\n## Stages\n\n" + pipeline::FormatStageMarkdown(r.stages);
  if (r.dataset_summary) {
    std::ostringstream table;
    PrintDatasetTable(table, *r.dataset_summary);
    md += "\n## Dataset (as `ultrafusion info` prints it)\n\n```\n" + table.str() + "```\n";
  }
  const pipeline::OdometrySummary& o = r.odometry;
  md += "\n## Counts\n\n| item | count |\n|---|---|\n";
  if (o.step == "scan") {
    md += "| LiDAR scans fed | " + std::to_string(o.scans) + " |\n";
    md += "| keyframes (trajectory poses) | " + std::to_string(o.keyframes) + " |\n";
    md += "| scans skipped by the odometry | " + std::to_string(o.skipped) + " |\n";
  } else {
    md += "| nodes solved | " + std::to_string(o.timing.steps) + " |\n";
    md += "| trajectory poses | " + std::to_string(o.keyframes) + " |\n";
  }
  md += "| wall time [s] | " + FormatValue("%.2f", r.wall_seconds) + " |\n";
  if (o.step == "scan") md += FormatTracking(o.track_events, o.scans) + FormatReliability(o);
  if (o.wheel_scored > 0) md += FormatWheelReliability(o);
  if (o.gnss_scored > 0) md += FormatGnssReliability(o);
  if (o.imu_scored > 0) md += FormatImuReliability(o);
  if (o.camera_scored > 0) md += FormatCameraReliability(o);
  if (o.imu_states > 0) md += FormatImuStates(o);
  if (o.online_calibration && o.calibration_estimates)
    md += FormatOnlineCalibration(*o.online_calibration, *o.calibration_estimates);
  md += "\n## Timing per " + o.step + " (" + (o.step == "scan" ? "AddScan" : "the node's solve") +
        " + TakeFinished, wall time)\n\n";
  md += "| mean [ms] | median [ms] | p95 [ms] | max [ms] |\n|---|---|---|---|\n";
  md += "| " + FormatValue("%.2f", o.timing.mean) + " | " + FormatValue("%.2f", o.timing.median) + " | " +
        FormatValue("%.2f", o.timing.p95) + " | " + FormatValue("%.2f", o.timing.max) + " |\n";
  if (o.stage_means) {
    const pipeline::StageTimes& s = *o.stage_means;
    md += "\nMean per scan by stage [ms]: preparation " + FormatValue("%.2f", s.prepare) + ", association " +
          FormatValue("%.2f", s.associate) + ", registration " + FormatValue("%.2f", s.register_scan) +
          ", window solve " + FormatValue("%.2f", s.window) + ", map " + FormatValue("%.2f", s.map) +
          ", marginalization " + FormatValue("%.2f", s.marginalize) + " (also in `timing.json`).\n";
  }
  if (!o.timing_plot.empty()) md += "\n![time per " + o.step + "](" + o.timing_plot + ")\n";
  if (!o.visual.plot.empty()) md += FormatVisual(o.visual, o.step);
  if (r.map) md += "\n## Map\n\n" + r.map->summary + "\n\nFiles: " + r.map->files + "\n";
  if (r.splat) {
    const SplatSummary splat = Summarize(*r.splat);
    md += "\n## Splats\n\n| metric | value |\n|---|---|\n";
    for (const auto& [name, value] : splat.metrics) md += "| " + name + " | " + value + " |\n";
    if (!r.splat_views.empty()) md += "\n" + r.splat_views + "\n";
    if (!splat.comparison.empty())
      md += "\nA held-out image (left) and the splats rendered at its pose (right):\n\n![held-out view](" +
            splat.comparison + ")\n";
    if (!splat.loss_plot.empty()) md += "\n![splat training loss](" + splat.loss_plot + ")\n";
  }
  md += "\n## Accuracy\n\n";
  if (r.accuracy.evaluated) {
    md += "ATE (APE translation RMSE, SE3-aligned): " + FormatValue("%.4f", r.accuracy.ape_rmse_m) + " m\n\n";
    if (r.accuracy.yaw_ape_rmse_m)
      md +=
          "ATE aligned by yaw and translation only (the run's world is gravity-aligned, so a tilt of it "
          "counts): " +
          FormatValue("%.4f", *r.accuracy.yaw_ape_rmse_m) + " m\n\n";
    if (r.accuracy.ground_truth_moved_to_output_frame)
      md +=
          "Ground truth: the dataset's, of its body frame, taken to trajectory.tum's frame with the "
          "extrinsic of the calibration: reference.tum.\n\n";
    if (!r.accuracy.reference_source.empty())
      md += "Ground truth: no file came with the data; the reader's reference, " +
            r.accuracy.reference_source + ", in trajectory.tum's frame: reference.tum.\n\n";
    if (const std::optional<pipeline::EnuAccuracy>& enu = r.accuracy.enu)
      md += "Position error in ENU without alignment (the estimator's georeference, " +
            std::to_string(enu->matched_poses) + " poses): RMSE " + FormatValue("%.4f", enu->rmse_m) +
            " m, horizontal " + FormatValue("%.4f", enu->horizontal_rmse_m) + " m, vertical " +
            FormatValue("%.4f", enu->vertical_rmse_m) + " m\n\n";
    if (!r.accuracy.enu_note.empty()) md += r.accuracy.enu_note + "\n\n";
    md += "As `ultrafusion eval GROUND_TRUTH trajectory.tum --align se3` reports it:\n\n```\n" +
          r.accuracy.table + "```\n\n";
    for (const std::string& plot : r.accuracy.plots) md += "![" + plot + "](" + plot + ")\n";
  }
  if (!r.accuracy.note.empty()) md += r.accuracy.note + "\n";
  if (const std::optional<GnssTrackError>& track = r.accuracy.gnss_track) {
    md += "\nAgainst the GNSS track (" + std::to_string(track->fixes) + " fixes over " +
          FormatValue("%.1f", track->track_length_m) + " m; " +
          (track->aligned ? "the trajectory fitted to them, yaw and translation in a gravity-aligned world"
                          : "the estimator's georeference, no alignment") +
          "; the fixes' own noise included): horizontal RMSE " +
          FormatValue("%.3f", track->horizontal_rmse_m) + " m, vertical " +
          FormatValue("%.3f", track->vertical_rmse_m) + " m";
    if (track->segment_error_percent)
      md += "; relative horizontal error over " + FormatValue("%.0f", track->segment_m) + " m of track " +
            FormatValue("%.2f", *track->segment_error_percent) + " %";
    md += "\n";
  }
  if (!r.accuracy.gnss_track_note.empty()) md += r.accuracy.gnss_track_note + "\n";
  if (r.accuracy.gnss_track)
    for (const std::string& plot : r.accuracy.plots) md += "\n![" + plot + "](" + plot + ")\n";
  md += "\n## Warnings\n\n";
  const std::vector<ReadWarning> odometry = GroupWarnings(o.odometry_warnings);
  const std::vector<ReadWarning> map = r.map ? GroupWarnings(r.map->warnings) : std::vector<ReadWarning>{};
  if (o.reader_warnings.empty() && odometry.empty() && map.empty()) {
    md += "none\n";
  } else {
    md += "| source | stream | what (first occurrence) | count |\n|---|---|---|---|\n";
    AppendWarnings(md, o.reader_warnings, "reader");
    AppendWarnings(md, odometry, "odometry");
    AppendWarnings(md, map, "map");
  }
  md += "\n## Configuration (config.yaml)\n\n";
  if (!r.repeat_command.empty()) md += "Repeat the run with `" + r.repeat_command + "`\n\n";
  md += "```yaml\n" + r.config_yaml + "```\n";
  return md;
}

Status WriteRunReports(const fs::path& out, const pipeline::RunSummary& summary) {
  const std::string markdown = FormatRunReport(summary);
  if (Status s = pipeline::WriteTextFileAtomically(out / "report.md", markdown); !s.ok()) return s;
  return pipeline::WriteTextFileAtomically(out / "report.html",
                                           MarkdownReportToHtml(markdown, out, "ultrafusion run"));
}

}  // namespace uf::app
