// Every measurement of a dataset reader, for tests that look at the whole stream.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "odometry/io/dataset_reader.h"

namespace uf::testing {

// Every measurement until the end, in the reader's order; a read error fails the test and ends the list.
inline std::vector<Measurement> ReadAll(DatasetReader& reader) {
  std::vector<Measurement> all;
  while (true) {
    auto next = reader.Next();
    if (!next.ok()) {
      ADD_FAILURE() << next.error();
      return all;
    }
    if (!next->has_value()) return all;
    all.push_back(std::move(**next));
  }
}

}  // namespace uf::testing
