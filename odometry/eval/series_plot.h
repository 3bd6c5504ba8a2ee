// A PNG plot of one to three series over time (PLplot's pngcairo device, 1280x960, the style of plots.h):
// each as a line with a dot at each value (one series blue; three in red, green, blue, as x, y, z), and
// optionally a horizontal line at one value (e.g. the value a calibration locked), all in a legend. Rendered
// to a temporary file and renamed onto png_path only when complete; bad input (empty, mismatched or
// non-finite values, |value| > 1e9) is an error naming the path, and no file is left behind.
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

struct NamedSeries {
  std::string label;
  std::vector<double> values;
};

// `seconds` as the x axis shows them; seconds.size() == values.size(), not empty.
Status WriteSeriesPlot(const std::string& png_path, const std::vector<double>& seconds,
                       const std::vector<double>& values, const std::string& series_label,
                       const std::optional<SeriesLevel>& level, const std::string& title,
                       const std::string& x_label, const std::string& y_label);

// The same for 1-3 series over the same stamps, each seconds.size() long.
Status WriteSeriesPlot(const std::string& png_path, const std::vector<double>& seconds,
                       const std::vector<NamedSeries>& series, const std::optional<SeriesLevel>& level,
                       const std::string& title, const std::string& x_label, const std::string& y_label);

}  // namespace uf
