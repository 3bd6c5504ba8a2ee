// Choosing a trajectory file's format: by name, or from its first data line.
#include "odometry/io/text_table.h"
#include "odometry/io/trajectory_file.h"

namespace uf {

Expected<TrajectoryFormat> ParseTrajectoryFormat(std::string_view name) {
  if (name == "auto") return TrajectoryFormat::kAuto;
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  return Status::Error("unknown trajectory format '" + std::string(name) + "' (auto, tum, kitti, euroc)");
}

const char* TrajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum:
      return "TUM";
    case TrajectoryFormat::kKitti:
      return "KITTI";
    case TrajectoryFormat::kEuroc:
      return "EuRoC";
    case TrajectoryFormat::kAuto:
      break;
  }
  return "auto";
}

Expected<TrajectoryFormat> DetectTrajectoryFormat(const std::string& path) {
  auto opened = TextTableReader::Open(path);
  if (!opened) return opened.status();
  TextTableReader& in = *opened;
  if (!in.Next()) return Status::Error(path + ": no data lines (empty file or only comments)");
  const bool integer_first = in.field(0).find_first_not_of("0123456789") == std::string_view::npos;
  if (in.comma_separated() && integer_first && in.columns() >= 8) return TrajectoryFormat::kEuroc;
  if (in.columns() == 12) return TrajectoryFormat::kKitti;
  if (in.columns() == 8) return TrajectoryFormat::kTum;
  return in.Error("cannot tell the trajectory format from " + std::to_string(in.columns()) +
                  " columns: expected TUM (8: t x y z qx qy qz qw), KITTI (12: 3x4 matrix row-major) or "
                  "EuRoC CSV (t[ns], x, y, z, qw, qx, qy, qz, ...)");
}

Expected<Trajectory> ReadTrajectory(const std::string& path, TrajectoryFormat format,
                                    const TrajectoryReadOptions& options, TrajectoryReadReport* report) {
  if (format == TrajectoryFormat::kAuto) {
    auto detected = DetectTrajectoryFormat(path);
    if (!detected) return detected.status();
    format = *detected;
  }
  switch (format) {
    case TrajectoryFormat::kTum:
      return ReadTumTrajectory(path, options, report);
    case TrajectoryFormat::kEuroc:
      return ReadEurocTrajectory(path, options, report);
    case TrajectoryFormat::kKitti:
      if (report) report->format = format;
      return ReadKittiTrajectory(path);
    case TrajectoryFormat::kAuto:
      break;
  }
  return Status::Error(path + ": no format");
}

}  // namespace uf
