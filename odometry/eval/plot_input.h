// Internal to odometry/eval (the PNG plots of plots.h); not to be included from elsewhere.
// Checking the caller's values before plotting and preparing the caller's text for PLplot.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "odometry/types/status.h"

namespace uf::plot {

// Values beyond these magnitudes are refused: PLplot's tick labels (at most kAxisDigits digits) could not
// tell the ticks of a metre-sized trajectory apart. Stamps may be larger, as the plot counts from the first.
constexpr double kMaxValue = 1e9, kMaxSeconds = 1e12;

// Longest text kept, in characters (longer text is cut and ends in an ellipsis).
constexpr std::size_t kMaxTextChars = 120;     // titles and axis labels (shrunk to fit their edge)
constexpr std::size_t kMaxBarLabelChars = 45;  // the colour bar label (drawn at full size)

// A value with 4 significant digits ("%.4g"), as the plots and their error messages show it.
std::string FormatValue(double value);

// OK if `value` is finite and |value| <= limit; else an error naming png_path and `name`.
Status CheckPlottable(const std::string& png_path, const std::string& name, double value, double limit);
// The same for every element; the error names it as name[i].
Status CheckPlottable(const std::string& png_path, const std::string& name, const std::vector<double>& values,
                      double limit);
// The same for every coordinate, within kMaxValue; the error names it as name[i].x (.y, .z).
Status CheckPlottable(const std::string& png_path, const std::string& name,
                      const std::vector<Eigen::Vector3d>& points);

// Text as PLplot draws it literally: '#' starts a PLplot escape sequence, so it is doubled; control
// characters and invalid UTF-8 become '?'; text longer than max_characters is cut and ends in an ellipsis.
std::string PlplotText(const std::string& text, std::size_t max_characters);

}  // namespace uf::plot
