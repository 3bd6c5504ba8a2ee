// PNG plots for trajectory evaluation, drawn with PLplot's pngcairo device (1280x960, white background).
// Each plot is rendered to "<png_path>.tmp<pid>" and renamed onto png_path only when complete; bad input or
// a PLplot failure returns an error naming the path and leaves no file behind (an existing png_path is kept).
// Thread-safe (PLplot keeps global state, so plots render one at a time). PLplot's fatal errors are caught:
// the process never exits, and nothing is printed. Values must be finite and within +-1e12.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "odometry/eval/statistics.h"
#include "odometry/types/status.h"

namespace uf {

// Top view (x-y) of the reference (grey line) and the estimate (line segments coloured by `error`, a colour
// bar labelled with `error_label`), equal axis scaling, axes labelled "x [m]" / "y [m]", legend, title.
// error.size() == estimate.size(); reference may have a different length; none empty.
Status WriteTopViewPlot(const std::string& png_path, const std::vector<Eigen::Vector3d>& reference,
                        const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& error,
                        const std::string& title, const std::string& error_label);

// Error over time: the error series against seconds (from the first stamp), with horizontal lines for rmse,
// mean and median (labelled in a legend with their values) and a shaded +-std band around the mean.
// seconds.size() == error.size(); none empty.
Status WriteErrorPlot(const std::string& png_path, const std::vector<double>& seconds,
                      const std::vector<double>& error, const ErrorStats& stats, const std::string& title,
                      const std::string& x_label, const std::string& y_label);

}  // namespace uf
