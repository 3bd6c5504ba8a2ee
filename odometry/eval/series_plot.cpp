#include "odometry/eval/series_plot.h"

#include <plplot.h>

#include <algorithm>
#include <array>

#include "odometry/eval/plot_draw.h"
#include "odometry/eval/plot_input.h"
#include "odometry/eval/plot_layout.h"
#include "odometry/eval/plot_png.h"
#include "odometry/eval/plot_style.h"

namespace uf::plot {
namespace {

constexpr PLFLT kLegendSample = 0.06;  // length of a legend's line sample, of the viewport width
constexpr PLFLT kLegendRowFraction = 0.065;
constexpr PLFLT kViewportBottom = 0.11, kViewportTop = 0.91;

constexpr std::size_t kMaxSeries = 3;

// The colour of series i of n: one is blue, three are red, green, blue (x, y, z).
PLINT SeriesColour(std::size_t i, std::size_t n) {
  constexpr std::array<PLINT, kMaxSeries> kXyz = {kRmse, kMean, kSeries};
  return n == 1 ? kSeries : kXyz[i];
}

// Everything the drawing needs, prepared before PLplot is touched (see DrawFunction).
struct SeriesScene {
  std::vector<PLFLT> t;
  std::vector<std::vector<PLFLT>> v;
  std::vector<std::string> labels;
  bool has_level = false;
  double level = 0;
  Box window{};
  std::string title, x_label, y_label, level_label;
};

SeriesScene MakeSeriesScene(const std::vector<double>& seconds, const std::vector<NamedSeries>& series,
                            const std::optional<SeriesLevel>& level, const std::string& title,
                            const std::string& x_label, const std::string& y_label) {
  SeriesScene scene;
  scene.t = seconds;
  const auto [t_lo, t_hi] = std::minmax_element(scene.t.begin(), scene.t.end());
  double x0 = *t_lo, x1 = *t_hi, y0 = series[0].values[0], y1 = y0;
  for (const NamedSeries& s : series) {
    scene.v.push_back(s.values);
    scene.labels.push_back(PlplotText(s.label, kMaxTextChars));
    const auto [v_lo, v_hi] = std::minmax_element(s.values.begin(), s.values.end());
    y0 = std::min(y0, *v_lo);
    y1 = std::max(y1, *v_hi);
  }
  if (level) {
    scene.has_level = true;
    scene.level = level->value;
    y0 = std::min(y0, level->value);
    y1 = std::max(y1, level->value);
    scene.level_label = PlplotText(level->label, kMaxTextChars);
  }
  WidenIfFlat(x0, x1);
  WidenIfFlat(y0, y1);
  const double margin = 0.05 * (y1 - y0);
  y0 -= margin;
  y1 += margin;
  y1 = y0 + (y1 - y0) / (1.0 - 2 * kLegendRowFraction);  // room above the data for the legend
  scene.window = {x0, x1, y0, y1};
  scene.title = PlplotText(title, kMaxTextChars);
  scene.x_label = PlplotText(x_label, kMaxTextChars);
  scene.y_label = PlplotText(y_label, kMaxTextChars);
  return scene;
}

void DrawSeriesPlot(const void* data) {
  const SeriesScene& s = *static_cast<const SeriesScene*>(data);
  // Layout: the y tick labels set the left margin.
  const TimePlotFrame frame = BeginTimePlot(s.window, kViewportBottom, kViewportTop);
  const Box& viewport = frame.viewport;
  const PLFLT x_tick = frame.x_tick, y_label_displacement = frame.y_label_displacement;
  if (s.has_level) {
    plcol0(kMean);
    pllsty(5);
    plwidth(2.2);
    pljoin(s.window.x0, s.level, s.window.x1, s.level);
    pllsty(1);
  }
  plwidth(2.0);
  const std::size_t n = s.v.size();
  for (std::size_t k = 0; k < n; ++k) {
    plcol0(SeriesColour(k, n));
    if (s.t.size() > 1) plline(static_cast<PLINT>(s.t.size()), s.t.data(), s.v[k].data());
    for (std::size_t i = 0; i < s.t.size(); ++i) DrawDot(s.t[i], s.v[k][i], viewport, s.window, 4.0);
  }
  DrawAxes(viewport, x_tick, y_label_displacement, s.x_label.c_str(), s.y_label.c_str(), s.title.c_str());

  constexpr std::size_t kMaxEntries = kMaxSeries + 1;
  const int entries = static_cast<int>(n) + (s.has_level ? 1 : 0);
  PLINT opts[kMaxEntries], text_colours[kMaxEntries], line_colours[kMaxEntries], line_styles[kMaxEntries];
  const char* text[kMaxEntries];
  PLFLT line_widths[kMaxEntries];
  for (int e = 0; e < entries; ++e) {
    const bool is_level = e == static_cast<int>(n);
    opts[e] = PL_LEGEND_LINE;
    text[e] = is_level ? s.level_label.c_str() : s.labels[e].c_str();
    text_colours[e] = kInk;
    line_colours[e] = is_level ? kMean : SeriesColour(e, n);
    line_styles[e] = is_level ? 5 : 1;
    line_widths[e] = is_level ? 2.2 : 2.0;
  }
  const PLFLT text_scale =
      LegendTextScale(text, entries, entries, kLegendSample, (viewport.x1 - viewport.x0) * kWidthPx, 0.9);
  PLFLT legend_width = 0, legend_height = 0;
  pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX | PL_LEGEND_ROW_MAJOR,
           PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE | PL_POSITION_VIEWPORT, 0.015, 0.015,
           kLegendSample, kBackground, kGrid, 1, 1, entries, entries, opts, 0.8, text_scale, 2.0, 0.0,
           text_colours, text, nullptr, nullptr, nullptr, nullptr, line_colours, line_styles, line_widths,
           nullptr, nullptr, nullptr, nullptr);
}

}  // namespace
}  // namespace uf::plot

namespace uf {

Status WriteSeriesPlot(const std::string& png_path, const std::vector<double>& seconds,
                       const std::vector<double>& values, const std::string& series_label,
                       const std::optional<SeriesLevel>& level, const std::string& title,
                       const std::string& x_label, const std::string& y_label) {
  return WriteSeriesPlot(png_path, seconds, {NamedSeries{series_label, values}}, level, title, x_label,
                         y_label);
}

Status WriteSeriesPlot(const std::string& png_path, const std::vector<double>& seconds,
                       const std::vector<NamedSeries>& series, const std::optional<SeriesLevel>& level,
                       const std::string& title, const std::string& x_label, const std::string& y_label) {
  if (series.empty() || series.size() > plot::kMaxSeries)
    return Status::Error("plot " + png_path + ": " + std::to_string(series.size()) +
                         " series, expected 1 to " + std::to_string(plot::kMaxSeries));
  for (const NamedSeries& s : series) {
    if (s.values.empty()) return Status::Error("plot " + png_path + ": the series is empty");
    if (seconds.size() != s.values.size())
      return Status::Error("plot " + png_path + ": " + std::to_string(seconds.size()) + " stamps for " +
                           std::to_string(s.values.size()) + " values");
    if (Status st = plot::CheckPlottable(png_path, "values", s.values, plot::kMaxValue); !st.ok()) return st;
  }
  if (Status s = plot::CheckPlottable(png_path, "seconds", seconds, plot::kMaxSeconds); !s.ok()) return s;
  if (level)
    if (Status s = plot::CheckPlottable(png_path, "level", level->value, plot::kMaxValue); !s.ok()) return s;
  const plot::SeriesScene scene = plot::MakeSeriesScene(seconds, series, level, title, x_label, y_label);
  return plot::WritePng(png_path, plot::DrawSeriesPlot, &scene);
}

}  // namespace uf
