// What the benchmark programs share to report their figures: a percentile of per-item times and the
// machine's load average (the figures are only comparable at a known load).
#pragma once

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace uf::bench {

// The q-quantile (q in [0, 1]) by rounding to the nearest rank; 0 for no values.
inline double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5)];
}

// "0.52 0.61 0.70": the 1, 5 and 15 minute load averages of /proc/loadavg ("" where it cannot be read).
inline std::string LoadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return in ? one + " " + five + " " + fifteen : "";
}

}  // namespace uf::bench
