// The machinery the folder readers share: each stream's file is a StreamSource read one record at a time,
// and MergedStreamsReader merges the sources' heads by stamp (a k-way merge; k is a handful, so the smallest
// head is found by a linear scan). Memory stays bounded by one record per stream. Internal to uf_io.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/warning_log.h"

namespace uf {

// One stream's file, read record by record in increasing stamp order.
class StreamSource {
 public:
  virtual ~StreamSource() = default;
  // Moves to the next record: false at the end of the stream. Errors name the file and line (or byte
  // offset); a stamp that does not increase is an error too.
  virtual Expected<bool> Advance() = 0;
  // Stamp of the current record (after Advance returned true).
  virtual Stamp stamp() const = 0;
  // The current record as a measurement, reading the files it refers to now (scans, images). nullopt skips
  // the record after noting why in `warnings`. May fill what only the data tells into `info`.
  virtual Expected<std::optional<MeasurementData>> Load(StreamInfo& info, WarningLog& warnings) = 0;
};

// Checks that a source's stamps increase strictly; the error text is completed by the caller.
class IncreasingStamps {
 public:
  // Empty when `stamp` is after the previous one, else "stamp S ns is not after the previous stamp P ns".
  std::string Check(Stamp stamp);

 private:
  bool has_previous_ = false;
  Stamp previous_ = 0;
};

// A DatasetReader over one source per stream (sources[i] delivers description.streams[i]); Next() gives the
// source with the earliest head (ties: the lower stream index).
class MergedStreamsReader : public DatasetReader {
 public:
  // Reads the first record of every source.
  static Expected<std::unique_ptr<MergedStreamsReader>> Create(
      DatasetDescription description, std::vector<std::unique_ptr<StreamSource>> sources);

  const DatasetDescription& description() const override { return description_; }
  Expected<std::optional<Measurement>> Next() override;
  const std::vector<ReadWarning>& warnings() const override { return warnings_.entries(); }

 private:
  MergedStreamsReader(DatasetDescription description, std::vector<std::unique_ptr<StreamSource>> sources);

  DatasetDescription description_;
  std::vector<std::unique_ptr<StreamSource>> sources_;
  std::vector<bool> has_head_;
  WarningLog warnings_;
  Status failure_;  // sticky: once a source fails, Next() repeats the error
};

}  // namespace uf
