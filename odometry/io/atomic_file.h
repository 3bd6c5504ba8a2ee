// Writes a file under a temporary name beside its destination and renames it into place on Commit(), so a
// failed or interrupted write never leaves a half file under the final name (nor replaces a good one).
#pragma once

#include <fstream>
#include <string>

#include "odometry/types/status.h"

namespace uf {

class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::string path);
  ~AtomicFileWriter();  // removes the temporary file unless committed
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  // Whether the temporary file could be created; the status names the path otherwise.
  Status status() const;
  std::ofstream& stream() { return out_; }
  // Flushes, checks for write errors (a full disk shows up here) and renames into place.
  Status Commit();

 private:
  std::string path_, temporary_path_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace uf
