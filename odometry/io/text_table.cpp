#include "odometry/io/text_table.h"

#include <charconv>
#include <cmath>
#include <fstream>

namespace uf {
std::string QuotedForError(std::string_view text) {
  constexpr std::size_t kMax = 40;
  std::string shown(text.substr(0, kMax));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return "'" + shown + (text.size() > kMax ? "...'" : "'");
}

Expected<TextTableReader> TextTableReader::Open(const std::string& path) {
  TextTableReader reader;
  reader.path_ = path;
  reader.in_ = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*reader.in_) return Status::Error(path + ": cannot open file");
  return reader;
}

Status TextTableReader::read_status() const {
  if (in_->bad()) return Status::Error(path_ + ": read error after line " + std::to_string(line_number_));
  return {};
}

bool TextTableReader::Next() {
  while (std::getline(*in_, line_)) {
    std::string_view line(line_);
    ++line_number_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    fields_.clear();
    comma_separated_ = line.find(',') != std::string_view::npos;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i == line.size()) break;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != ',') ++j;
      fields_.push_back(line.substr(i, j - i));
      i = j;
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i < line.size() && line[i] == ',') ++i;
    }
    if (fields_.empty() || fields_[0].front() == '#' || fields_[0].front() == '%') continue;
    return true;
  }
  fields_.clear();
  return false;
}

Status TextTableReader::Error(const std::string& what) const {
  return Status::Error(path_ + ":" + std::to_string(line_number_) + ": " + what);
}

Status TextTableReader::ExpectColumns(std::size_t count, const char* layout, bool at_least) const {
  if (columns() == count || (at_least && columns() > count)) return {};
  return Error("expected " + std::string(at_least ? "at least " : "") + std::to_string(count) + " columns (" +
               layout + "), found " + std::to_string(columns()));
}

Expected<double> TextTableReader::Number(std::size_t column, const char* name) const {
  std::string_view text = fields_[column];
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  const std::string where = std::string(name) + " (column " + std::to_string(column + 1) + ")";
  if (error == std::errc::result_out_of_range)
    return Error(where + " is out of the range of a double: " + QuotedForError(fields_[column]));
  if (error != std::errc() || end != text.data() + text.size())
    return Error(where + " is not a number: " + QuotedForError(fields_[column]));
  if (!std::isfinite(value)) return Error(where + " is not finite: " + QuotedForError(fields_[column]));
  return value;
}

Expected<Stamp> TextTableReader::Seconds(std::size_t column, const char* name) const {
  if (auto stamp = ParseSeconds(fields_[column])) return *stamp;
  return Error(std::string(name) + " (column " + std::to_string(column + 1) +
               ") is not a time in seconds: " + QuotedForError(fields_[column]));
}

Expected<Stamp> TextTableReader::Nanoseconds(std::size_t column, const char* name) const {
  std::string_view text = fields_[column];
  Stamp value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    return Error(std::string(name) + " (column " + std::to_string(column + 1) +
                 ") is not an integer time in nanoseconds: " + QuotedForError(text));
  return value;
}

Expected<bool> StampOrderCheck::Add(const TextTableReader& reader, Stamp stamp) {
  if (has_previous_ && stamp == previous_ && skip_duplicates_) {
    if (skipped_++ == 0) first_skipped_line_ = reader.line_number();
    return false;
  }
  if (has_previous_ && stamp <= previous_) {
    const std::string kind = stamp == previous_ ? "duplicate stamp " : "stamp goes backwards: ";
    return reader.Error(kind + FormatSeconds(stamp) + " s after " + FormatSeconds(previous_) + " s on line " +
                        std::to_string(previous_line_));
  }
  has_previous_ = true;
  previous_ = stamp;
  previous_line_ = reader.line_number();
  return true;
}

}  // namespace uf
