#include "viewer/app/report/info_report.h"

#include <cstdio>
#include <iomanip>
#include <nlohmann/json.hpp>

namespace uf::app {
namespace {

// A camera calibration as JSON, and as one line: "radial-tangential 752x480, fx fy cx cy [...], distortion
// [...]".
nlohmann::json CameraJson(const CameraModel& camera) {
  nlohmann::json j = {{"width", camera.width()}, {"height", camera.height()}};
  if (const auto* radtan = dynamic_cast<const PinholeRadtan*>(&camera)) {
    const PinholeRadtanIntrinsics& k = radtan->intrinsics();
    j["model"] = "radial-tangential";
    j["intrinsics"] = {k.pinhole.fx, k.pinhole.fy, k.pinhole.cx, k.pinhole.cy};
    j["distortion"] = {k.k1, k.k2, k.p1, k.p2, k.k3};
  } else if (const auto* fisheye = dynamic_cast<const Equidistant*>(&camera)) {
    const EquidistantIntrinsics& k = fisheye->intrinsics();
    j["model"] = "equidistant";
    j["intrinsics"] = {k.pinhole.fx, k.pinhole.fy, k.pinhole.cx, k.pinhole.cy};
    j["distortion"] = {k.k1, k.k2, k.k3, k.k4};
  }
  return j;
}

std::string CameraLine(const CameraModel& camera) {
  const nlohmann::json j = CameraJson(camera);
  std::string line = j.value("model", "camera") + " " + std::to_string(camera.width()) + "x" +
                     std::to_string(camera.height()) + ", fx fy cx cy " + j["intrinsics"].dump() +
                     ", distortion " + j["distortion"].dump();
  return line;
}

std::string Fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string Cell(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

// The convention of azimuth-derived point times and, when the check ran, its scores.
void PrintPointTimes(std::ostream& out, const pipeline::PointTimeSelection& times,
                     const std::string& indent) {
  out << indent << "azimuth convention: " << times.Line() << "\n";
  if (!times.check) return;
  const estimator::PointTimeCheckResult& check = *times.check;
  for (const estimator::ConventionScore& score : check.scores)
    out << indent << "  " << Cell(AzimuthConventionText(score.convention), 34) << "point-to-plane "
        << Fixed(score.score_m, 4) << " m (" << score.points << " points, " << score.keyframes
        << " keyframes)\n";
  out << indent << "  check: " << check.scans_read << " scans read, " << check.scans_used << " compared ("
      << check.moving_scans << " moving" << (check.separate_sweeps ? "; separate sweeps" : "") << "), "
      << Fixed(check.seconds, 1) << " s\n";
}

// The ground-truth file, or the reference the reader derived (with its pose count and frame).
std::string GroundTruthText(const DatasetDescription& d) {
  if (d.ground_truth) return d.ground_truth->string();
  if (!d.reference) return "none found";
  const std::size_t stream = static_cast<std::size_t>(d.reference->stream);
  return "none beside the data; reference: " + d.reference->source + ", " +
         std::to_string(d.reference->poses.size()) + " poses of " +
         (stream < d.streams.size() ? d.streams[stream].name : std::string("?"));
}

void PrintStreamDetails(std::ostream& out, const StreamSummary& s,
                        const std::optional<pipeline::PointTimeSelection>& times) {
  const std::string indent = "    ";
  if (!s.info.frame_id.empty()) out << indent << "frame: " << s.info.frame_id << "\n";
  if (s.info.kind == SensorKind::kLidar) {
    out << indent << "point time: ";
    if (s.info.point_time == PointTimeConvention::kNone)
      out << "none (scans cannot be deskewed per point)\n";
    else if (s.info.point_time_field.empty())
      out << PointTimeConventionName(s.info.point_time) << "\n";
    else
      out << "field '" << s.info.point_time_field << "', " << PointTimeConventionName(s.info.point_time)
          << "\n";
    if (times && times->stream == s.info.name) PrintPointTimes(out, *times, indent);
    if (s.points_per_scan) {
      out << indent << "points per scan: " << s.points_per_scan->min << " .. " << s.points_per_scan->max
          << " (mean " << Fixed(s.points_per_scan->mean, 0) << ")\n";
    }
  }
  if (s.info.camera_model) out << indent << "calibration: " << CameraLine(*s.info.camera_model) << "\n";
  if (!s.info.note.empty()) out << indent << "note: " << s.info.note << "\n";
  if (s.info.kind == SensorKind::kImu && !s.info.imu_accel_unit.empty()) {
    out << indent << "acceleration unit: " << s.info.imu_accel_unit
        << (s.info.imu_accel_unit == "g" ? " (converted to m/s^2)" : "") << "\n";
  }
  if (s.time.count > 1) {
    out << indent << "period: median " << Fixed(s.time.median_period_s * 1e3, 3) << " ms, jitter "
        << Fixed(s.time.jitter_percent, 1) << "%, gaps " << s.time.gaps << ", backwards " << s.time.backwards
        << ", duplicates " << s.time.duplicates << ", out of order " << s.time.out_of_order << "\n";
  }
  for (const std::string& finding : s.time.findings) out << indent << "! " << finding << "\n";
}

}  // namespace

void PrintDatasetTable(std::ostream& out, const DatasetSummary& summary) {
  const DatasetDescription& d = summary.description;
  out << "dataset: " << d.path.string() << " (" << DatasetFormatName(d.format) << ", "
      << Fixed(summary.bytes / 1e6, 1) << " MB read in " << Fixed(summary.read_seconds, 2) << " s)\n";
  out << "ground truth: " << GroundTruthText(d) << "\n\n";
  out << Cell("stream", 34) << Cell("kind", 7) << Cell("type", 30) << Cell("count", 8) << Cell("rate Hz", 9)
      << Cell("first [s]", 22) << Cell("last [s]", 22) << "verdict\n";
  for (const StreamSummary& s : summary.streams) {
    out << Cell(s.info.name, 34) << Cell(std::string(SensorKindName(s.info.kind)), 7)
        << Cell(s.info.message_type, 30) << Cell(std::to_string(s.time.count), 8)
        << Cell(Fixed(s.time.rate_hz, 2), 9) << Cell(s.time.count ? FormatSeconds(s.time.first) : "-", 22)
        << Cell(s.time.count ? FormatSeconds(s.time.last) : "-", 22) << StreamVerdictName(s.time.verdict)
        << "\n";
    PrintStreamDetails(out, s, summary.point_times);
  }
  if (!summary.warnings.empty()) out << "\nwarnings (recovered by skipping data):\n";
  for (const ReadWarning& w : summary.warnings)
    out << "  " << w.stream << ": " << w.what << " (" << w.count << ")\n";
}

void PrintDatasetJson(std::ostream& out, const DatasetSummary& summary) {
  using nlohmann::json;
  const DatasetDescription& d = summary.description;
  json streams = json::array();
  for (const StreamSummary& s : summary.streams) {
    json j = {{"name", s.info.name},
              {"kind", SensorKindName(s.info.kind)},
              {"message_type", s.info.message_type},
              {"frame_id", s.info.frame_id},
              {"count", s.time.count},
              {"rate_hz", s.time.rate_hz},
              {"first_stamp_ns", s.time.first},
              {"last_stamp_ns", s.time.last},
              {"median_period_s", s.time.median_period_s},
              {"jitter_percent", s.time.jitter_percent},
              {"gaps", s.time.gaps},
              {"largest_gap_s", s.time.largest_gap_s},
              {"backwards", s.time.backwards},
              {"duplicates", s.time.duplicates},
              {"out_of_order", s.time.out_of_order},
              {"verdict", StreamVerdictName(s.time.verdict)},
              {"findings", s.time.findings}};
    if (s.info.kind == SensorKind::kLidar) {
      j["point_time_field"] = s.info.point_time_field;
      j["point_time"] = PointTimeConventionName(s.info.point_time);
      if (s.info.azimuth_convention)
        j["azimuth_convention"] = AzimuthConventionKey(*s.info.azimuth_convention);
      if (s.points_per_scan) {
        j["points_per_scan"] = {{"min", s.points_per_scan->min},
                                {"max", s.points_per_scan->max},
                                {"mean", s.points_per_scan->mean}};
      }
    }
    if (s.info.kind == SensorKind::kImu) j["imu_accel_unit"] = s.info.imu_accel_unit;
    if (s.info.camera_model) j["calibration"] = CameraJson(*s.info.camera_model);
    if (s.info.kind == SensorKind::kCamera) j["camera"] = s.info.camera;
    if (s.info.nominal_rate_hz > 0) j["nominal_rate_hz"] = s.info.nominal_rate_hz;
    streams.push_back(std::move(j));
  }
  json warnings = json::array();
  for (const ReadWarning& w : summary.warnings)
    warnings.push_back({{"stream", w.stream}, {"what", w.what}, {"count", w.count}});
  json point_times = nullptr;
  if (const std::optional<pipeline::PointTimeSelection>& times = summary.point_times) {
    point_times = {
        {"stream", times->stream},
        {"convention", times->convention ? json(AzimuthConventionKey(*times->convention)) : json()},
        {"source", times->source},
        {"line", times->Line()}};
    if (const std::optional<estimator::PointTimeCheckResult>& check = times->check) {
      json scores = json::array();
      for (const estimator::ConventionScore& score : check->scores)
        scores.push_back({{"convention", AzimuthConventionKey(score.convention)},
                          {"score_m", score.score_m},
                          {"points", score.points},
                          {"keyframes", score.keyframes}});
      point_times["check"] = {{"current", AzimuthConventionKey(check->current)},
                              {"chosen", AzimuthConventionKey(check->chosen)},
                              {"compared", check->compared},
                              {"scans_read", check->scans_read},
                              {"scans_used", check->scans_used},
                              {"moving_scans", check->moving_scans},
                              {"separate_sweeps", check->separate_sweeps},
                              {"seconds", check->seconds},
                              {"reason", check->reason},
                              {"scores", scores}};
    }
  }
  json root = {{"dataset", d.path.string()},
               {"format", DatasetFormatName(d.format)},
               {"ground_truth", d.ground_truth ? json(d.ground_truth->string()) : json(nullptr)},
               {"reference", d.reference ? json(GroundTruthText(d)) : json(nullptr)},
               {"bytes", summary.bytes},
               {"read_seconds", summary.read_seconds},
               {"streams", streams},
               {"point_times", point_times},
               {"warnings", warnings}};
  out << std::setw(2) << root << "\n";
}

}  // namespace uf::app
