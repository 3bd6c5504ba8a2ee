// The text files of a KITTI raw drive: timestamp files (one wall-clock time per line, KITTI's
// "2011-09-26 13:08:24.969505176", read as UTC) and the calibration files (`key: numbers` per line).
// Internal to uf_io; the reader is kitti_raw_reader.cpp.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf {

// "2011-09-26 13:08:24.969505176" -> ns since the Unix epoch, the time read as UTC (KITTI writes local
// wall-clock time without a zone; taking it as UTC keeps every stream of a drive on one clock, which is all
// the estimator needs, and matches how KITTI tools convert it). 0 to 9 fraction digits; nullopt for
// anything else (including impossible dates such as 2011-02-30, and years outside 1970-2200).
std::optional<Stamp> ParseKittiWallClock(std::string_view text);

// A timestamps.txt: one entry per frame, the line number being the frame index. An empty line (KITTI marks
// frames that were lost so) is nullopt; a line that does not parse is an error naming file, line and text.
Expected<std::vector<std::optional<Stamp>>> ReadKittiTimestamps(const std::filesystem::path& path);

// A calib_*.txt: `key: v1 v2 ...` per line. Numbers are parsed where all of a value's words are numbers;
// other values (calib_time: 09-Jan-2012 13:57:47) are kept out. A key given twice is an error.
using KittiCalibValues = std::map<std::string, std::vector<double>, std::less<>>;
Expected<KittiCalibValues> ReadKittiCalibFile(const std::filesystem::path& path);

// The `count` numbers of `key`, or an error naming the file and the key.
Expected<std::vector<double>> CalibNumbers(const KittiCalibValues& values, std::string_view key,
                                           std::size_t count, const std::filesystem::path& file);

}  // namespace uf
