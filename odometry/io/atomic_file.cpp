#include "odometry/io/atomic_file.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <system_error>

namespace uf {

AtomicFileWriter::AtomicFileWriter(std::string path)
    : path_(std::move(path)), temporary_path_(path_ + ".tmp" + std::to_string(::getpid())) {
  out_.open(temporary_path_, std::ios::binary | std::ios::trunc);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_path_, ignored);
}

Status AtomicFileWriter::status() const {
  if (out_.is_open()) return {};
  return Status::Error(path_ + ": cannot create file (is the folder there and writable?)");
}

Status AtomicFileWriter::Commit() {
  if (Status s = status(); !s.ok()) return s;
  out_.flush();
  const bool write_failed = !out_;
  out_.close();
  if (write_failed || out_.fail()) return Status::Error(path_ + ": write failed (disk full?)");
  std::error_code error;
  std::filesystem::rename(temporary_path_, path_, error);
  if (error) return Status::Error(path_ + ": cannot move the written file into place: " + error.message());
  committed_ = true;
  return {};
}

}  // namespace uf
