// Helpers of the sequence generator's tests.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "odometry/io/dataset_reader.h"

namespace uf::sim {

// Every measurement of a dataset, in the reader's order; a read error fails the test and ends the list.
inline std::vector<Measurement> ReadAll(DatasetReader& reader) {
  std::vector<Measurement> all;
  while (true) {
    auto next = reader.Next();
    EXPECT_TRUE(next.ok()) << next.error();
    if (!next.ok() || !next->has_value()) return all;
    all.push_back(std::move(**next));
  }
}

}  // namespace uf::sim
