// The recoverable damage a reader met, as DatasetReader::warnings() reports it: one entry per stream and
// kind of damage, with a running count. The kind is the text before " (": the rest carries the values of
// the first occurrence (kept as the example), so "NaN points dropped (scan at 12.3 s)" and the same with
// another stamp count as one kind.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "odometry/io/dataset_reader.h"

namespace uf {

class WarningLog {
 public:
  void Add(const std::string& stream, const std::string& what, std::int64_t count = 1);
  const std::vector<ReadWarning>& entries() const { return entries_; }

 private:
  std::vector<ReadWarning> entries_;
  std::map<std::pair<std::string, std::string>, std::size_t> index_;  // (stream, kind) -> entry
};

}  // namespace uf
