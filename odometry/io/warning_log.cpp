#include "odometry/io/warning_log.h"

namespace uf {

void WarningLog::Add(const std::string& stream, const std::string& what, std::int64_t count) {
  const std::string kind = what.substr(0, what.find(" ("));
  const auto [entry, added] = index_.emplace(std::make_pair(stream, kind), entries_.size());
  if (added) entries_.push_back(ReadWarning{stream, what, 0});
  entries_[entry->second].count += count;
}

}  // namespace uf
