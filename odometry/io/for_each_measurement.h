// The measurement loop every consumer of a dataset runs: take the next measurement until the source ends,
// stop at the first read error, hand each one to a handler that may stop the loop with an error of its own.
// Works on a DatasetReader (storage order) and on a MeasurementStream (time order): both have
// Expected<std::optional<Measurement>> Next().
#pragma once

#include <optional>

#include "odometry/io/dataset_reader.h"

namespace uf {

// Calls handle(Measurement&) -> Status on each measurement of `source` in its order. Returns the first
// error of the source or of the handler, ok at the end of the source.
template <typename Source, typename Handler>
Status ForEachMeasurement(Source& source, Handler&& handle) {
  while (true) {
    Expected<std::optional<Measurement>> next = source.Next();
    if (!next) return next.status();
    if (!next->has_value()) return {};
    if (Status s = handle(**next); !s.ok()) return s;
  }
}

}  // namespace uf
