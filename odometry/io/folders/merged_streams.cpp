#include "odometry/io/folders/merged_streams.h"

#include <cassert>

namespace uf {

std::string IncreasingStamps::Check(Stamp stamp) {
  if (has_previous_ && stamp <= previous_)
    return "stamp " + std::to_string(stamp) + " ns is not after the previous stamp " +
           std::to_string(previous_) + " ns";
  has_previous_ = true;
  previous_ = stamp;
  return {};
}

MergedStreamsReader::MergedStreamsReader(DatasetDescription description,
                                         std::vector<std::unique_ptr<StreamSource>> sources)
    : description_(std::move(description)), sources_(std::move(sources)), has_head_(sources_.size(), false) {}

Expected<std::unique_ptr<MergedStreamsReader>> MergedStreamsReader::Create(
    DatasetDescription description, std::vector<std::unique_ptr<StreamSource>> sources) {
  assert(description.streams.size() == sources.size());
  std::unique_ptr<MergedStreamsReader> reader(
      new MergedStreamsReader(std::move(description), std::move(sources)));
  for (std::size_t i = 0; i < reader->sources_.size(); ++i) {
    auto advanced = reader->sources_[i]->Advance();
    if (!advanced) return advanced.status();
    reader->has_head_[i] = *advanced;
  }
  return reader;
}

Expected<std::optional<Measurement>> MergedStreamsReader::Next() {
  while (failure_.ok()) {
    // The earliest head; on equal stamps the lower stream index goes first.
    int earliest = -1;
    for (std::size_t i = 0; i < sources_.size(); ++i) {
      if (!has_head_[i]) continue;
      if (earliest < 0 || sources_[i]->stamp() < sources_[earliest]->stamp()) earliest = static_cast<int>(i);
    }
    if (earliest < 0) return std::optional<Measurement>();

    StreamSource& source = *sources_[earliest];
    auto loaded = source.Load(description_.streams[earliest], warnings_);
    if (!loaded) {
      failure_ = loaded.status();
      break;
    }
    // A damaged next record fails the next call: the measurement in hand is still good.
    auto advanced = source.Advance();
    if (!advanced) failure_ = advanced.status();
    has_head_[earliest] = advanced && *advanced;
    if (*loaded) return std::optional<Measurement>(Measurement{earliest, std::move(**loaded)});
  }
  return failure_;
}

}  // namespace uf
