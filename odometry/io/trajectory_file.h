// Trajectory files: TUM (`t x y z qx qy qz qw`, seconds), KITTI (12 values of the 3x4 matrix [R|t] per line,
// row-major; stamps from an optional times file) and EuRoC ground-truth CSV (`t[ns], x, y, z, qw, qx, qy,
// qz`, further columns ignored). Readers validate every value and name file and line on error; writers keep
// nanosecond-exact stamps and never leave a half-written file.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

enum class TrajectoryFormat { kAuto, kTum, kKitti, kEuroc };

struct TrajectoryReadOptions {
  // Keep the first pose of each run of equal stamps instead of failing (evo's association behaves so).
  bool skip_duplicate_stamps = false;
};

struct TrajectoryReadReport {
  TrajectoryFormat format = TrajectoryFormat::kAuto;  // the format read
  std::size_t skipped_duplicates = 0;
  int first_skipped_line = 0;
};

Expected<TrajectoryFormat> ParseTrajectoryFormat(std::string_view name);  // auto|tum|kitti|euroc
const char* TrajectoryFormatName(TrajectoryFormat format);

// Decides from the first data line: comma-separated with an integer first field -> EuRoC, 12 columns ->
// KITTI, 8 columns -> TUM.
Expected<TrajectoryFormat> DetectTrajectoryFormat(const std::string& path);

Expected<Trajectory> ReadTrajectory(const std::string& path,
                                    TrajectoryFormat format = TrajectoryFormat::kAuto,
                                    const TrajectoryReadOptions& options = {},
                                    TrajectoryReadReport* report = nullptr);
Expected<Trajectory> ReadTumTrajectory(const std::string& path, const TrajectoryReadOptions& options = {},
                                       TrajectoryReadReport* report = nullptr);
Expected<Trajectory> ReadKittiTrajectory(const std::string& path);  // no stamps
Expected<Trajectory> ReadEurocTrajectory(const std::string& path, const TrajectoryReadOptions& options = {},
                                         TrajectoryReadReport* report = nullptr);

// One stamp per line in seconds (KITTI times.txt), exact to the nanosecond; must increase strictly. Blank
// lines and '#' comments (a whole line, or after the time) are skipped.
Expected<std::vector<Stamp>> ReadTimesFile(const std::string& path);
// The same lines in any order, repeats allowed (the times `ultrafusion render --stamps` renders at). Errors
// name the file, the line and the text that is not a time ("stamps.txt:3: time (column 1) is not a time in
// seconds: 'abc'").
Expected<std::vector<Stamp>> ReadStampsFile(const std::string& path);
// Attaches stamps to a stampless (KITTI) trajectory; the counts must agree.
Status AttachStamps(Trajectory& trajectory, std::vector<Stamp> stamps, const std::string& times_path);

Status WriteTumTrajectory(const std::string& path, const Trajectory& trajectory);
Status WriteKittiTrajectory(const std::string& path, const Trajectory& trajectory);
Status WriteEurocTrajectory(const std::string& path, const Trajectory& trajectory);  // needs stamps

}  // namespace uf
