#include "odometry/eval/plots.h"

#include <plplot.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <utility>

#include "odometry/eval/plot_draw.h"
#include "odometry/eval/plot_input.h"
#include "odometry/eval/plot_layout.h"
#include "odometry/eval/plot_png.h"
#include "odometry/eval/plot_style.h"

namespace uf::plot {
namespace {

constexpr int kColourBarSteps = 256;     // colours in the top view's colour bar
constexpr PLFLT kLegendTextScale = 0.9;  // relative to kTextScale
constexpr PLFLT kLegendSample = 0.06;    // length of a legend's line sample, of the viewport width
// Of the viewport height, kept free above the data for each row of a legend.
constexpr PLFLT kLegendRowFraction = 0.065;
constexpr PLFLT kViewportBottom = 0.11, kViewportTop = 0.91;  // normalized page coordinates
constexpr PLINT kLevelStyles[3] = {5, 1, 3};  // PLplot line styles of the rmse, mean and median lines

// Everything a top view needs, prepared before PLplot is touched (see DrawFunction for why).
struct TopViewScene {
  std::vector<PLFLT> ref_x, ref_y, est_x, est_y;
  std::vector<PLFLT> colour;  // cmap1 position of each estimate segment (of the single point if only one)
  double error_lo = 0, error_hi = 1;
  Box data{};  // bounding box of both trajectories in x-y
  std::string title, error_label;
};

struct ErrorScene {
  std::vector<PLFLT> t, e;
  double rmse = 0, mean = 0, median = 0, std = 0;
  Box window{};
  std::string title, x_label, y_label;
  std::array<std::string, 5> entries;  // error, rmse, mean, median, band
};

// ---------------------------------------------------------------------------------------------------------
// Top view

Status CheckTopViewInput(const std::string& png_path, const std::vector<Eigen::Vector3d>& reference,
                         const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& error) {
  if (reference.empty()) return Status::Error("plot " + png_path + ": the reference trajectory is empty");
  if (estimate.empty()) return Status::Error("plot " + png_path + ": the estimated trajectory is empty");
  if (error.size() != estimate.size())
    return Status::Error("plot " + png_path + ": " + std::to_string(error.size()) + " error values for " +
                         std::to_string(estimate.size()) + " estimated poses");
  if (Status s = CheckPlottable(png_path, "reference", reference); !s.ok()) return s;
  if (Status s = CheckPlottable(png_path, "estimate", estimate); !s.ok()) return s;
  return CheckPlottable(png_path, "error", error, kMaxValue);
}

// Coordinates, their bounding box, segment colours, text.
TopViewScene MakeTopViewScene(const std::vector<Eigen::Vector3d>& reference,
                              const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& error,
                              const std::string& title, const std::string& error_label) {
  TopViewScene scene;
  Box data{std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
           std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest()};
  const auto add = [&data](const std::vector<Eigen::Vector3d>& points, std::vector<PLFLT>& xs,
                           std::vector<PLFLT>& ys) {
    for (const Eigen::Vector3d& p : points) {
      xs.push_back(p.x());
      ys.push_back(p.y());
      data = {std::min(data.x0, p.x()), std::max(data.x1, p.x()), std::min(data.y0, p.y()),
              std::max(data.y1, p.y())};
    }
  };
  add(reference, scene.ref_x, scene.ref_y);
  add(estimate, scene.est_x, scene.est_y);
  const auto [lo, hi] = std::minmax_element(error.begin(), error.end());
  scene.error_lo = *lo;
  scene.error_hi = *hi;
  WidenIfFlat(scene.error_lo, scene.error_hi);
  // A segment takes the colour of its mean error, mapped linearly from [error_lo, error_hi] to [0, 1].
  const double to_unit = 1.0 / (scene.error_hi - scene.error_lo);
  const auto unit = [&](double e) { return std::clamp((e - scene.error_lo) * to_unit, 0.0, 1.0); };
  if (error.size() == 1) scene.colour.push_back(unit(error[0]));
  for (std::size_t i = 0; i + 1 < error.size(); ++i)
    scene.colour.push_back(unit(0.5 * (error[i] + error[i + 1])));
  scene.data = data;
  scene.title = PlplotText(title, kMaxTextChars);
  scene.error_label = PlplotText(error_label, kMaxBarLabelChars);
  return scene;
}

void DrawTopView(const void* data) {
  const TopViewScene& s = *static_cast<const TopViewScene*>(data);

  // Layout: the colour bar's tick labels set the right margin, the y tick labels the left one. Those depend
  // on the window and the window on the viewport, so two passes settle them.
  const PLFLT char_px = CharHeightPx();
  Box viewport{0.0, 1.0 - ColourBarMargin(TickLabelCharacters(s.error_lo, s.error_hi)) * char_px / kWidthPx,
               kViewportBottom, kViewportTop};
  Box window = s.data;
  PLFLT y_label_displacement = 0;
  for (int pass = 0; pass < 2; ++pass) {
    y_label_displacement = YLabelDisplacement(TickLabelCharacters(window.y0, window.y1));
    viewport.x0 = (y_label_displacement + kLeftOfYLabel) * char_px / kWidthPx;
    window = EqualScaleWindow(s.data, viewport, kLegendRowFraction);
  }
  const PLFLT x_tick = XTickSpacing(viewport, window, char_px);
  DrawGrid(viewport, window, x_tick);

  // Reference in grey, then the estimate segment by segment in the colour of its error.
  plcol0(kReference);
  plwidth(2.5);
  if (s.ref_x.size() > 1)
    plline(static_cast<PLINT>(s.ref_x.size()), s.ref_x.data(), s.ref_y.data());
  else
    DrawDot(s.ref_x[0], s.ref_y[0], viewport, window, 7.0);
  plwidth(3.0);
  if (s.est_x.size() > 1) {
    for (std::size_t i = 0; i + 1 < s.est_x.size(); ++i) {
      plcol1(s.colour[i]);
      pljoin(s.est_x[i], s.est_y[i], s.est_x[i + 1], s.est_y[i + 1]);
    }
  } else {
    plcol1(s.colour[0]);
    DrawDot(s.est_x[0], s.est_y[0], viewport, window, 4.5);
  }
  DrawAxes(viewport, x_tick, y_label_displacement, "x [m]", "y [m]", s.title.c_str());

  // Colour bar right of the viewport over [error_lo, error_hi], with its own axis and label. It is an image
  // of evenly spaced values, not a gradient: PLplot's cairo driver leaks every gradient fill.
  const PLFLT viewport_px = (viewport.x1 - viewport.x0) * kWidthPx;
  PLFLT steps[kColourBarSteps];
  for (int i = 0; i < kColourBarSteps; ++i)
    steps[i] = s.error_lo + (s.error_hi - s.error_lo) * i / (kColourBarSteps - 1);
  const PLFLT* values[1] = {steps};
  const PLINT n_values[1] = {kColourBarSteps};
  const char* axis_opts[1] = {"bcvtm"};
  const PLFLT ticks[1] = {0.0};
  const PLINT sub_ticks[1] = {0};
  const PLINT label_opts[1] = {PL_COLORBAR_LABEL_RIGHT};
  const char* labels[1] = {s.error_label.c_str()};
  PLFLT bar_width = 0, bar_height = 0;
  plcol0(kInk);
  plwidth(1.0);
  plcolorbar(&bar_width, &bar_height, PL_COLORBAR_IMAGE,
             PL_POSITION_RIGHT | PL_POSITION_OUTSIDE | PL_POSITION_VIEWPORT, kBarGap * char_px / viewport_px,
             0.0, kBarWidth * char_px / viewport_px, 1.0, kBackground, kInk, 1, 0.0, 0.0, kInk, 1.0, 1,
             label_opts, labels, 1, axis_opts, ticks, sub_ticks, n_values, values);

  // Legend in one row at the top, where the window leaves room above the data.
  const PLINT opts[2] = {PL_LEGEND_LINE, PL_LEGEND_LINE};
  const char* text[2] = {"reference", "estimate"};
  const PLINT text_colours[2] = {kInk, kInk};
  const PLINT line_colours[2] = {kReference, kEstimate};
  const PLINT line_styles[2] = {1, 1};
  const PLFLT line_widths[2] = {3.0, 3.0};
  PLFLT legend_width = 0, legend_height = 0;
  pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
           PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE | PL_POSITION_VIEWPORT, 0.015, 0.015,
           kLegendSample, kBackground, kGrid, 1, 1, 2, 2, opts, 0.8, 1.0, 2.0, 0.0, text_colours, text,
           nullptr, nullptr, nullptr, nullptr, line_colours, line_styles, line_widths, nullptr, nullptr,
           nullptr, nullptr);
}

// ---------------------------------------------------------------------------------------------------------
// Error over time

Status CheckErrorPlotInput(const std::string& png_path, const std::vector<double>& seconds,
                           const std::vector<double>& error, const ErrorStats& stats) {
  if (error.empty()) return Status::Error("plot " + png_path + ": the error series is empty");
  if (seconds.size() != error.size())
    return Status::Error("plot " + png_path + ": " + std::to_string(seconds.size()) + " stamps for " +
                         std::to_string(error.size()) + " error values");
  if (Status s = CheckPlottable(png_path, "seconds", seconds, kMaxSeconds); !s.ok()) return s;
  if (Status s = CheckPlottable(png_path, "error", error, kMaxValue); !s.ok()) return s;
  for (const auto& [name, value] :
       {std::pair{"stats.rmse", stats.rmse}, std::pair{"stats.mean", stats.mean},
        std::pair{"stats.median", stats.median}, std::pair{"stats.std", stats.std}})
    if (Status s = CheckPlottable(png_path, name, value, kMaxValue); !s.ok()) return s;
  return Status();
}

// Time from the first stamp, a window with room for the legend at the top, text.
ErrorScene MakeErrorScene(const std::vector<double>& seconds, const std::vector<double>& error,
                          const ErrorStats& stats, const std::string& title, const std::string& x_label,
                          const std::string& y_label) {
  ErrorScene scene;
  for (double t : seconds) scene.t.push_back(t - seconds.front());
  scene.e = error;
  scene.rmse = stats.rmse;
  scene.mean = stats.mean;
  scene.median = stats.median;
  scene.std = stats.std;
  const auto [t_lo, t_hi] = std::minmax_element(scene.t.begin(), scene.t.end());
  const auto [e_lo, e_hi] = std::minmax_element(error.begin(), error.end());
  double x0 = *t_lo, x1 = *t_hi;
  WidenIfFlat(x0, x1);
  double y0 = std::min({0.0, *e_lo, stats.mean - stats.std, stats.rmse, stats.median});
  double y1 = std::max({*e_hi, stats.mean + stats.std, stats.rmse, stats.median});
  WidenIfFlat(y0, y1);
  if (y0 < 0) y0 -= 0.03 * (y1 - y0);
  y1 = y0 + (y1 - y0) / (1.0 - 3 * kLegendRowFraction);  // room above the data for three legend rows
  scene.window = {x0, x1, y0, y1};
  scene.title = PlplotText(title, kMaxTextChars);
  scene.x_label = PlplotText(x_label, kMaxTextChars);
  scene.y_label = PlplotText(y_label, kMaxTextChars);
  scene.entries = {"error", "rmse = " + FormatValue(stats.rmse), "mean = " + FormatValue(stats.mean),
                   "median = " + FormatValue(stats.median),
                   "mean ± std (std = " + FormatValue(stats.std) + ")"};
  return scene;
}

void DrawErrorPlot(const void* data) {
  const ErrorScene& s = *static_cast<const ErrorScene*>(data);

  // Layout: the y tick labels set the left margin.
  const TimePlotFrame frame = BeginTimePlot(s.window, kViewportBottom, kViewportTop);
  const Box& viewport = frame.viewport;
  const PLFLT x_tick = frame.x_tick, y_label_displacement = frame.y_label_displacement;

  // +-std band around the mean across the whole time axis, the statistics as lines, the series on top.
  const PLFLT band_x[4] = {s.window.x0, s.window.x1, s.window.x1, s.window.x0};
  const PLFLT band_y[4] = {s.mean - s.std, s.mean - s.std, s.mean + s.std, s.mean + s.std};
  plcol0(kBand);
  plfill(4, band_x, band_y);
  const PLFLT levels[3] = {s.rmse, s.mean, s.median};
  const PLINT level_colours[3] = {kRmse, kMean, kMedian};
  for (int i = 0; i < 3; ++i) {
    plcol0(level_colours[i]);
    pllsty(kLevelStyles[i]);
    plwidth(2.2);
    pljoin(s.window.x0, levels[i], s.window.x1, levels[i]);
  }
  pllsty(1);
  plcol0(kSeries);
  plwidth(2.0);
  if (s.t.size() > 1)
    plline(static_cast<PLINT>(s.t.size()), s.t.data(), s.e.data());
  else
    DrawDot(s.t[0], s.e[0], viewport, s.window, 4.5);
  DrawAxes(viewport, x_tick, y_label_displacement, s.x_label.c_str(), s.y_label.c_str(), s.title.c_str());

  // Legend in three rows at the top, where the window leaves room above the data.
  const PLINT opts[5] = {PL_LEGEND_LINE, PL_LEGEND_LINE, PL_LEGEND_LINE, PL_LEGEND_LINE, PL_LEGEND_COLOR_BOX};
  const char* text[5] = {s.entries[0].c_str(), s.entries[1].c_str(), s.entries[2].c_str(),
                         s.entries[3].c_str(), s.entries[4].c_str()};
  const PLINT text_colours[5] = {kInk, kInk, kInk, kInk, kInk};
  const PLINT line_colours[5] = {kSeries, kRmse, kMean, kMedian, kBackground};
  const PLINT line_styles[5] = {1, kLevelStyles[0], kLevelStyles[1], kLevelStyles[2], 1};
  const PLFLT line_widths[5] = {2.0, 2.2, 2.2, 2.2, 1.0};
  const PLINT box_colours[5] = {kBackground, kBackground, kBackground, kBackground, kBand};
  const PLINT box_patterns[5] = {0, 0, 0, 0, 0};
  const PLFLT box_scales[5] = {0.8, 0.8, 0.8, 0.8, 0.8};
  const PLFLT box_line_widths[5] = {1.0, 1.0, 1.0, 1.0, 1.0};
  const PLFLT text_scale =
      LegendTextScale(text, 5, 2, kLegendSample, (viewport.x1 - viewport.x0) * kWidthPx, kLegendTextScale);
  PLFLT legend_width = 0, legend_height = 0;
  pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX | PL_LEGEND_ROW_MAJOR,
           PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE | PL_POSITION_VIEWPORT, 0.015, 0.015,
           kLegendSample, kBackground, kGrid, 1, 3, 2, 5, opts, 0.8, text_scale, 2.0, 0.0, text_colours, text,
           box_colours, box_patterns, box_scales, box_line_widths, line_colours, line_styles, line_widths,
           nullptr, nullptr, nullptr, nullptr);
}

}  // namespace
}  // namespace uf::plot

namespace uf {

Status WriteTopViewPlot(const std::string& png_path, const std::vector<Eigen::Vector3d>& reference,
                        const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& error,
                        const std::string& title, const std::string& error_label) {
  if (Status s = plot::CheckTopViewInput(png_path, reference, estimate, error); !s.ok()) return s;
  const plot::TopViewScene scene = plot::MakeTopViewScene(reference, estimate, error, title, error_label);
  return plot::WritePng(png_path, plot::DrawTopView, &scene);
}

Status WriteErrorPlot(const std::string& png_path, const std::vector<double>& seconds,
                      const std::vector<double>& error, const ErrorStats& stats, const std::string& title,
                      const std::string& x_label, const std::string& y_label) {
  if (Status s = plot::CheckErrorPlotInput(png_path, seconds, error, stats); !s.ok()) return s;
  const plot::ErrorScene scene = plot::MakeErrorScene(seconds, error, stats, title, x_label, y_label);
  return plot::WritePng(png_path, plot::DrawErrorPlot, &scene);
}

}  // namespace uf
