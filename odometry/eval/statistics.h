// Summary statistics of an error series, defined as evo defines them (std is the population standard
// deviation, median the mean of the two middle values for an even count).
#pragma once

#include <cstddef>
#include <vector>

namespace uf {

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
  std::size_t n = 0;
};

// Precondition: errors is not empty.
ErrorStats ComputeStats(const std::vector<double>& errors);

}  // namespace uf
