// Reading back what `ultrafusion run` wrote, for the CLI tests: trajectory rows and the report's ATE.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.h"

namespace uf::testing {

// Numbers on each non-comment line of a text file.
inline std::vector<std::vector<double>> ReadRows(const std::string& path) {
  std::vector<std::vector<double>> rows;
  std::istringstream text(ReadText(path));
  std::string line;
  while (std::getline(text, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    for (double v; fields >> v;) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

// The number after "ATE (APE translation RMSE, SE3-aligned): " in report.md, or -1.
inline double ReportedAte(const std::string& report) {
  const std::string key = "ATE (APE translation RMSE, SE3-aligned): ";
  const std::size_t at = report.find(key);
  if (at == std::string::npos) return -1;
  return std::stod(report.substr(at + key.size()));
}

}  // namespace uf::testing
