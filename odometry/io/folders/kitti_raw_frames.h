// The frames of one stream of a KITTI raw drive: the files in <stream>/data/ named by their 10-digit frame
// index, each paired with line `index` of <stream>/timestamps.txt. Internal to uf_io.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "odometry/io/folders/merged_streams.h"
#include "odometry/io/warning_log.h"

namespace uf {

struct KittiFrame {
  std::int64_t index = 0;
  std::filesystem::path file;
  Stamp stamp = 0;
};

// Damage noticed while listing, reported through the reader's warnings with the stream's first measurement.
struct KittiListingNotes {
  std::int64_t without_stamp = 0;  // a file whose timestamps.txt line is empty or absent: skipped
  std::int64_t missing = 0;        // frame indices between the first and the last file with no file
  std::int64_t first_missing = -1;
  void Report(const std::string& stream, const std::string& what, WarningLog& warnings) const;
};

// Lists <folder>/data/ (files whose name is the frame index plus one of `extensions`, e.g. ".bin") in index
// order and stamps them from <folder>/<stamps_file>. Errors: no data/ folder, an unreadable or unparsable
// timestamps file, stamps that do not increase (naming both frames).
Expected<std::vector<KittiFrame>> ListKittiFrames(const std::filesystem::path& folder,
                                                  const std::vector<std::string>& extensions,
                                                  KittiListingNotes& notes,
                                                  const std::string& stamps_file = "timestamps.txt");

// The same stream's other timestamps file (velodyne_points/timestamps_start.txt, _end.txt) by frame index;
// nullopt when the file is absent.
Expected<std::optional<std::vector<std::optional<Stamp>>>> ReadOptionalKittiTimestamps(
    const std::filesystem::path& path);

// A StreamSource over listed frames: Advance walks them, Load calls `load` on the current one.
class KittiFrameSource : public StreamSource {
 public:
  using Loader =
      std::function<Expected<std::optional<MeasurementData>>(const KittiFrame&, StreamInfo&, WarningLog&)>;
  KittiFrameSource(std::vector<KittiFrame> frames, KittiListingNotes notes, std::string stream,
                   std::string what_missing, Loader load);

  Expected<bool> Advance() override { return ++next_ <= frames_.size(); }
  Stamp stamp() const override { return frames_[next_ - 1].stamp; }
  Expected<std::optional<MeasurementData>> Load(StreamInfo& info, WarningLog& warnings) override;

 private:
  std::vector<KittiFrame> frames_;
  KittiListingNotes notes_;
  std::string stream_, what_missing_;
  Loader load_;
  std::size_t next_ = 0;
  bool noted_ = false;
};

}  // namespace uf
