// A PNG plot of one series over time (PLplot's pngcairo device, 1280x960, the style of plots.h): the values
// as a line with a dot at each, and optionally a horizontal line at one value (e.g. the value a calibration
// locked), both in a legend. Rendered to a temporary file and renamed onto png_path only when complete; bad
// input (empty, mismatched or non-finite values, |value| > 1e9) is an error naming the path, and no file is
// left behind.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/types/status.h"

namespace uf {

struct SeriesLevel {
  double value = 0.0;
  std::string label;
};

// `seconds` as the x axis shows them; seconds.size() == values.size(), not empty.
Status WriteSeriesPlot(const std::string& png_path, const std::vector<double>& seconds,
                       const std::vector<double>& values, const std::string& series_label,
                       const std::optional<SeriesLevel>& level, const std::string& title,
                       const std::string& x_label, const std::string& y_label);

}  // namespace uf
