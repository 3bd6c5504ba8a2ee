// Line-by-line reader for the numeric text tables that trajectory, times and sensor CSV files are: fields
// separated by whitespace or commas, blank lines and lines starting with '#' or '%' skipped. Only the current
// line is held in memory (sensor CSVs of long recordings run to hundreds of megabytes). Every error it makes
// names the file and the line.
#pragma once

#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf {

class TextTableReader {
 public:
  static Expected<TextTableReader> Open(const std::string& path);

  // Advances to the next data row; false at the end of the file (or on a read error: see read_status()).
  bool Next();
  // An error when reading the file failed (an I/O error, not a format error); ok otherwise.
  Status read_status() const;

  const std::string& path() const { return path_; }
  int line_number() const { return line_number_; }
  std::size_t columns() const { return fields_.size(); }
  std::string_view field(std::size_t column) const { return fields_[column]; }
  bool comma_separated() const { return comma_separated_; }

  // "FILE:LINE: what"
  Status Error(const std::string& what) const;
  // Requires exactly `count` columns (or at least, with at_least).
  Status ExpectColumns(std::size_t count, const char* layout, bool at_least = false) const;
  // A finite decimal number in `column`; the error names the field and the text found.
  Expected<double> Number(std::size_t column, const char* name) const;
  // A stamp in seconds (exact to the nanosecond) or in integer nanoseconds.
  Expected<Stamp> Seconds(std::size_t column, const char* name) const;
  Expected<Stamp> Nanoseconds(std::size_t column, const char* name) const;

 private:
  std::string path_;
  std::unique_ptr<std::ifstream> in_;  // behind a pointer so the reader moves cheaply
  std::string line_;
  int line_number_ = 0;
  bool comma_separated_ = false;
  std::vector<std::string_view> fields_;
};

// Checks that stamps increase strictly; names the line of the first duplicate or backwards stamp. With
// `skip_duplicates` a row repeating the previous stamp is reported as to be skipped (false) instead.
class StampOrderCheck {
 public:
  explicit StampOrderCheck(bool skip_duplicates = false) : skip_duplicates_(skip_duplicates) {}
  // True: keep the row; false: skip it (a duplicate, when allowed); an error otherwise.
  Expected<bool> Add(const TextTableReader& reader, Stamp stamp);
  std::size_t skipped() const { return skipped_; }
  int first_skipped_line() const { return first_skipped_line_; }

 private:
  bool skip_duplicates_;
  std::size_t skipped_ = 0;
  int first_skipped_line_ = 0;
  bool has_previous_ = false;
  Stamp previous_ = 0;
  int previous_line_ = 0;
};

// Renders text for an error message: at most 40 characters, control bytes as '?', in quotes.
std::string QuotedForError(std::string_view text);

}  // namespace uf
