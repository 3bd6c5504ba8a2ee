#include "odometry/io/folders/kitti_raw_files.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

namespace uf {
namespace {

// The digits of text[at, at + n) as a number; nullopt unless all are digits.
std::optional<int> Digits(std::string_view text, std::size_t at, std::size_t n) {
  if (at + n > text.size()) return std::nullopt;
  int value = 0;
  for (std::size_t i = at; i < at + n; ++i) {
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

std::string_view Trimmed(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

}  // namespace

std::optional<Stamp> ParseKittiWallClock(std::string_view text) {
  text = Trimmed(text);
  // YYYY-MM-DD HH:MM:SS[.f...]
  if (text.size() < 19 || text[4] != '-' || text[7] != '-' || text[10] != ' ' || text[13] != ':' ||
      text[16] != ':')
    return std::nullopt;
  const auto year = Digits(text, 0, 4), month = Digits(text, 5, 2), day = Digits(text, 8, 2);
  const auto hour = Digits(text, 11, 2), minute = Digits(text, 14, 2), second = Digits(text, 17, 2);
  if (!year || !month || !day || !hour || !minute || !second) return std::nullopt;
  const std::chrono::year_month_day date{std::chrono::year(*year), std::chrono::month(*month),
                                         std::chrono::day(*day)};
  // Years past 2200 would overflow int64 nanoseconds near 2262 (a fuzzer found 2398); before 1970 no drive.
  if (!date.ok() || *year < 1970 || *year > 2200 || *hour > 23 || *minute > 59 || *second > 60)
    return std::nullopt;
  Stamp fraction_ns = 0;
  if (text.size() > 19) {
    const std::size_t digits = text.size() - 20;
    if (text[19] != '.' || digits > 9) return std::nullopt;
    const std::optional<int> fraction = digits == 0 ? 0 : Digits(text, 20, digits);
    if (!fraction) return std::nullopt;
    fraction_ns = *fraction;
    for (std::size_t i = digits; i < 9; ++i) fraction_ns *= 10;
  }
  const std::chrono::sys_seconds time = std::chrono::sys_days(date) + std::chrono::hours(*hour) +
                                        std::chrono::minutes(*minute) + std::chrono::seconds(*second);
  return static_cast<Stamp>(time.time_since_epoch().count()) * kNanosecondsPerSecond + fraction_ns;
}

Expected<std::vector<std::optional<Stamp>>> ReadKittiTimestamps(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path.string() + ": cannot open the timestamps file");
  std::vector<std::optional<Stamp>> stamps;
  std::string line;
  while (std::getline(in, line)) {
    if (Trimmed(line).empty()) {
      stamps.emplace_back();
      continue;
    }
    const std::optional<Stamp> stamp = ParseKittiWallClock(line);
    if (!stamp)
      return Status::Error(path.string() + ":" + std::to_string(stamps.size() + 1) + ": '" +
                           std::string(Trimmed(line).substr(0, 60)) +
                           "' is not a KITTI time (expected YYYY-MM-DD HH:MM:SS.fffffffff)");
    stamps.push_back(stamp);
  }
  if (in.bad()) return Status::Error(path.string() + ": read error");
  return stamps;
}

Expected<KittiCalibValues> ReadKittiCalibFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path.string() + ": cannot open the calibration file");
  KittiCalibValues values;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (Trimmed(line).empty()) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos)
      return Status::Error(path.string() + ":" + std::to_string(number) +
                           ": expected `key: values`, found '" + std::string(Trimmed(line).substr(0, 60)) +
                           "'");
    const std::string key(Trimmed(std::string_view(line).substr(0, colon)));
    std::istringstream words(line.substr(colon + 1));
    std::vector<double> numbers;
    bool all_numbers = true;
    for (std::string word; words >> word;) {
      double value = 0;
      auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
      if (error != std::errc() || end != word.data() + word.size() || !std::isfinite(value)) {
        all_numbers = false;
        break;
      }
      numbers.push_back(value);
    }
    if (values.contains(key))
      return Status::Error(path.string() + ":" + std::to_string(number) + ": key '" + key + "' given twice");
    if (all_numbers) values[key] = std::move(numbers);
  }
  if (in.bad()) return Status::Error(path.string() + ": read error");
  return values;
}

Expected<std::vector<double>> CalibNumbers(const KittiCalibValues& values, std::string_view key,
                                           std::size_t count, const std::filesystem::path& file) {
  const auto found = values.find(key);
  if (found == values.end())
    return Status::Error(file.string() + ": no '" + std::string(key) + ":' line (" + std::to_string(count) +
                         " numbers expected)");
  if (found->second.size() != count)
    return Status::Error(file.string() + ": '" + std::string(key) + ":' has " +
                         std::to_string(found->second.size()) + " numbers, expected " +
                         std::to_string(count));
  return found->second;
}

}  // namespace uf
