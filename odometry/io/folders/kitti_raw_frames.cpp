#include "odometry/io/folders/kitti_raw_frames.h"

#include <algorithm>
#include <charconv>

#include "odometry/io/folders/kitti_raw_files.h"

namespace uf {
namespace {

namespace fs = std::filesystem;

// "0000000042.bin" -> 42 when the name is digits plus one of the extensions.
std::optional<std::int64_t> FrameIndex(const std::string& name, const std::vector<std::string>& extensions) {
  for (const std::string& extension : extensions) {
    if (name.size() <= extension.size() || !name.ends_with(extension)) continue;
    const std::string_view digits(name.data(), name.size() - extension.size());
    std::int64_t index = 0;
    auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    if (error == std::errc() && end == digits.data() + digits.size() && index >= 0) return index;
  }
  return std::nullopt;
}

}  // namespace

void KittiListingNotes::Report(const std::string& stream, const std::string& what,
                               WarningLog& warnings) const {
  if (without_stamp > 0)
    warnings.Add(stream, "files without a stamp (empty or missing line in timestamps.txt) skipped",
                 without_stamp);
  if (missing > 0)
    warnings.Add(stream, what + " missing (first at frame " + std::to_string(first_missing) + ")", missing);
}

Expected<std::vector<KittiFrame>> ListKittiFrames(const fs::path& folder,
                                                  const std::vector<std::string>& extensions,
                                                  KittiListingNotes& notes, const std::string& stamps_file) {
  const fs::path data = folder / "data";
  std::error_code error;
  if (!fs::is_directory(data, error)) return Status::Error(data.string() + ": missing (the stream's files)");
  std::vector<std::pair<std::int64_t, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(data, error))
    if (entry.is_regular_file())
      if (const auto index = FrameIndex(entry.path().filename().string(), extensions))
        files.emplace_back(*index, entry.path());
  if (error) return Status::Error(data.string() + ": cannot list the folder: " + error.message());
  std::sort(files.begin(), files.end());
  for (std::size_t i = 1; i < files.size(); ++i)
    if (files[i].first == files[i - 1].first)
      return Status::Error(data.string() + ": two files for frame " + std::to_string(files[i].first) + ": " +
                           files[i - 1].second.filename().string() + " and " +
                           files[i].second.filename().string());

  auto stamps = ReadKittiTimestamps(folder / stamps_file);
  if (!stamps) return stamps.status();
  std::vector<KittiFrame> frames;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const auto [index, file] = files[i];
    if (i > 0 && index > files[i - 1].first + 1) {
      if (notes.first_missing < 0) notes.first_missing = files[i - 1].first + 1;
      notes.missing += index - files[i - 1].first - 1;
    }
    if (index >= static_cast<std::int64_t>(stamps->size()) || !(*stamps)[index]) {
      ++notes.without_stamp;
      continue;
    }
    const Stamp stamp = *(*stamps)[index];
    if (!frames.empty() && stamp <= frames.back().stamp)
      return Status::Error((folder / stamps_file).string() + ": the stamp of frame " + std::to_string(index) +
                           " (" + StampText(stamp) + ") is not after that of frame " +
                           std::to_string(frames.back().index) + " (" + StampText(frames.back().stamp) + ")");
    frames.push_back({index, file, stamp});
  }
  return frames;
}

Expected<std::optional<std::vector<std::optional<Stamp>>>> ReadOptionalKittiTimestamps(const fs::path& path) {
  std::error_code error;
  if (!fs::exists(path, error)) return std::optional<std::vector<std::optional<Stamp>>>();
  auto stamps = ReadKittiTimestamps(path);
  if (!stamps) return stamps.status();
  return std::optional(std::move(*stamps));
}

KittiFrameSource::KittiFrameSource(std::vector<KittiFrame> frames, KittiListingNotes notes,
                                   std::string stream, std::string what_missing, Loader load)
    : frames_(std::move(frames)),
      notes_(notes),
      stream_(std::move(stream)),
      what_missing_(std::move(what_missing)),
      load_(std::move(load)) {}

Expected<std::optional<MeasurementData>> KittiFrameSource::Load(StreamInfo& info, WarningLog& warnings) {
  if (!noted_) {
    notes_.Report(stream_, what_missing_, warnings);
    noted_ = true;
  }
  return load_(frames_[next_ - 1], info, warnings);
}

}  // namespace uf
