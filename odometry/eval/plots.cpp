#include "odometry/eval/plots.h"

#include <plplot.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>
#include <utility>

namespace uf {
namespace {

constexpr PLINT kWidthPx = 1280, kHeightPx = 960;

// Colour map 0 (PLplot's indexed colours); index 0 is the page background.
enum Colour : PLINT {
  kBackground,
  kInk,
  kGrid,
  kReference,
  kEstimate,
  kSeries,
  kRmse,
  kMean,
  kMedian,
  kBand
};
constexpr std::array<std::array<PLINT, 3>, 10> kColours{{
    {255, 255, 255},  // background
    {30, 30, 30},     // axes and text
    {225, 225, 225},  // grid
    {150, 150, 150},  // reference trajectory
    {48, 18, 59},     // estimate (legend only: the line itself is coloured by error)
    {31, 119, 180},   // error series
    {214, 39, 40},    // rmse
    {44, 160, 44},    // mean
    {255, 127, 14},   // median
    {44, 160, 44},    // +-std band (drawn translucent)
}};
constexpr PLFLT kBandAlpha = 0.18;
constexpr int kColourBarSteps = 256;

// Colour map 1 (error -> colour): Google's Turbo, sampled at 9 points and interpolated linearly in RGB.
constexpr std::array<std::array<PLFLT, 4>, 9> kTurbo{{
    {0.000, 0.190, 0.072, 0.232},
    {0.125, 0.255, 0.370, 0.820},
    {0.250, 0.180, 0.650, 0.980},
    {0.375, 0.110, 0.880, 0.760},
    {0.500, 0.420, 0.990, 0.360},
    {0.625, 0.760, 0.940, 0.210},
    {0.750, 0.990, 0.680, 0.200},
    {0.875, 0.900, 0.330, 0.060},
    {1.000, 0.480, 0.016, 0.011},
}};

// Text sizes are relative to PLplot's default character height; lengths in the layout are in character
// heights.
constexpr PLFLT kTextScale = 0.95;
constexpr PLFLT kTitleScale = 1.2;
constexpr std::size_t kMaxTextChars = 120;     // titles and axis labels (shrunk to fit their edge)
constexpr std::size_t kMaxBarLabelChars = 45;  // the colour bar label (drawn at full size)
constexpr PLINT kAxisDigits = 12;        // tick labels keep this many digits before PLplot adds "(x10^k)"
constexpr PLFLT kLegendTextScale = 0.9;  // relative to kTextScale
constexpr PLFLT kLegendSample = 0.06;    // length of a legend's line sample, of the viewport width
// Of the viewport height, kept free above the data for each row of a legend.
constexpr PLFLT kLegendRowFraction = 0.065;
constexpr PLFLT kViewportBottom = 0.11, kViewportTop = 0.91;  // normalized page coordinates
constexpr PLINT kLevelStyles[3] = {5, 1, 3};  // PLplot line styles of the rmse, mean and median lines

// A rectangle in world (data) or normalized coordinates.
struct Box {
  double x0, x1, y0, y1;
};

// Everything a top view needs, prepared before PLplot is touched (see RenderGuarded for why).
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
// Input checks and text preparation

std::string FormatValue(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}

// Values beyond these magnitudes are refused: PLplot's tick labels (at most kAxisDigits digits) could not
// tell the ticks of a metre-sized trajectory apart. Stamps may be larger, as the plot counts from the first.
constexpr double kMaxValue = 1e9, kMaxSeconds = 1e12;

Status CheckPlottable(const std::string& png_path, const std::string& name, double value, double limit) {
  if (!std::isfinite(value)) return Status::Error("plot " + png_path + ": " + name + " is not finite");
  if (std::abs(value) > limit)
    return Status::Error("plot " + png_path + ": " + name + " = " + FormatValue(value) +
                         " is too large to plot (limit " + FormatValue(limit) + ")");
  return Status();
}

Status CheckPlottable(const std::string& png_path, const std::string& name, const std::vector<double>& values,
                      double limit) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (Status s = CheckPlottable(png_path, name + "[" + std::to_string(i) + "]", values[i], limit); !s.ok())
      return s;
  return Status();
}

Status CheckPlottable(const std::string& png_path, const std::string& name,
                      const std::vector<Eigen::Vector3d>& points) {
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int axis = 0; axis < 3; ++axis) {
      const std::string field = name + "[" + std::to_string(i) + "]." + "xyz"[axis];
      if (Status s = CheckPlottable(png_path, field, points[i][axis], kMaxValue); !s.ok()) return s;
    }
  return Status();
}

// Length in bytes of the valid UTF-8 sequence starting at s[i], or 0 if it is not one.
std::size_t Utf8Length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const unsigned lead = byte(i);
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // allowed range of the second byte (excludes overlongs and surrogates)
  if (lead >= 0xC2 && lead <= 0xDF)
    n = 2;
  else if (lead >= 0xE0 && lead <= 0xEF)
    n = 3, lo = lead == 0xE0 ? 0xA0 : 0x80, hi = lead == 0xED ? 0x9F : 0xBF;
  else if (lead >= 0xF0 && lead <= 0xF4)
    n = 4, lo = lead == 0xF0 ? 0x90 : 0x80, hi = lead == 0xF4 ? 0x8F : 0xBF;
  else
    return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return n;
}

// Text as PLplot draws it literally: '#' starts a PLplot escape sequence, so it is doubled; control
// characters and invalid UTF-8 become '?'; text longer than max_characters is cut and ends in an ellipsis.
std::string PlplotText(const std::string& text, std::size_t max_characters) {
  std::string out;
  std::size_t i = 0;
  for (std::size_t characters = 0; i < text.size() && characters < max_characters; ++characters) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      out += c < 0x20 || c == 0x7F ? '?' : static_cast<char>(c);
      if (c == '#') out += '#';
      ++i;
    } else if (const std::size_t n = Utf8Length(text, i)) {
      out.append(text, i, n);
      i += n;
    } else {
      out += '?';
      ++i;
    }
  }
  if (i < text.size()) out += "\xE2\x80\xA6";  // U+2026 ellipsis
  return out;
}

// ---------------------------------------------------------------------------------------------------------
// Layout

// Grows [lo, hi] about its middle so that a degenerate range still spans `min_span`.
void EnsureSpan(double& lo, double& hi, double min_span) {
  if (hi - lo >= min_span) return;
  const double mid = 0.5 * (lo + hi);
  lo = mid - 0.5 * min_span;
  hi = mid + 0.5 * min_span;
}

// Widens a value range whose ends are (nearly) equal: to [0, 1] at zero, else by 5% of the value each side.
void WidenIfFlat(double& lo, double& hi) {
  const double magnitude = std::max(std::abs(lo), std::abs(hi));
  if (hi - lo > 1e-9 * magnitude) return;
  if (magnitude == 0) {
    lo = 0, hi = 1;
    return;
  }
  const double mid = 0.5 * (lo + hi);
  lo = mid - 0.05 * magnitude;
  hi = mid + 0.05 * magnitude;
}

// Equal axis scaling: one metre is as long in x as in y. The data box (padded by 5%) must fit the viewport
// below its top `legend_fraction`: metres per pixel = max(span_x / w_px, span_y / (h_px (1 -
// legend_fraction))). The data are centred in that area and the axis with room to spare is widened.
Box EqualScaleWindow(Box data, const Box& viewport, double legend_fraction) {
  EnsureSpan(data.x0, data.x1, 1.0);
  EnsureSpan(data.y0, data.y1, 1.0);
  const double pad = 0.05 * std::max(data.x1 - data.x0, data.y1 - data.y0);
  const double w_px = (viewport.x1 - viewport.x0) * kWidthPx, h_px = (viewport.y1 - viewport.y0) * kHeightPx;
  const double h_data_px = h_px * (1.0 - legend_fraction);
  const double m_per_px =
      std::max((data.x1 - data.x0 + 2 * pad) / w_px, (data.y1 - data.y0 + 2 * pad) / h_data_px);
  const double cx = 0.5 * (data.x0 + data.x1), cy = 0.5 * (data.y0 + data.y1);
  const double y0 = cy - 0.5 * h_data_px * m_per_px;
  return {cx - 0.5 * w_px * m_per_px, cx + 0.5 * w_px * m_per_px, y0, y0 + h_px * m_per_px};
}

// Characters of the longest tick label on an axis spanning [lo, hi], over-estimated: PLplot puts 3 to 10
// ticks on an axis and writes as many decimals as the tick spacing needs (at most span / 10).
int TickLabelCharacters(double lo, double hi) {
  const double span = hi > lo ? hi - lo : std::max({std::abs(lo), std::abs(hi), 1.0});
  const int decimals = std::clamp(-static_cast<int>(std::floor(std::log10(span / 10))), 0, 15);
  char buffer[64];
  return std::max(std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, lo),
                  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, hi));
}

// Width of a tick label character in character heights (PLplot's unit of text size), measured for DejaVu
// Sans digits drawn by the pngcairo device.
constexpr PLFLT kDigitWidth = 0.85;

// Spacing of the x ticks (PLplot's own choice ignores the label width): the smallest 1, 2 or 5 x 10^k that
// gives at most 6 ticks and leaves 1.5 label widths per tick.
PLFLT XTickSpacing(const Box& viewport, const Box& window, PLFLT char_px) {
  const double span = window.x1 - window.x0;
  const double label_px = kDigitWidth * char_px * TickLabelCharacters(window.x0, window.x1);
  const double ticks = std::clamp((viewport.x1 - viewport.x0) * kWidthPx / (1.5 * label_px), 1.0, 6.0);
  const double decade = std::pow(10.0, std::floor(std::log10(span / ticks)));
  for (double multiple : {1.0, 2.0, 5.0})
    if (multiple * decade >= span / ticks) return multiple * decade;
  return 10.0 * decade;
}

// Horizontal layout, in character heights: the y label's distance from the left axis so that it clears tick
// labels of `characters` digits, and the width left of the y label.
PLFLT YLabelDisplacement(int characters) { return 1.9 + kDigitWidth * characters; }
constexpr PLFLT kLeftOfYLabel = 0.9;

// The colour bar right of the viewport, in character heights: gap, bar, tick labels, gap, label, page edge.
constexpr PLFLT kBarGap = 1.0, kBarWidth = 1.5;
PLFLT ColourBarMargin(int characters) { return kBarGap + kBarWidth + 0.8 + kDigitWidth * characters + 3.0; }

// Character height in pixels (PLplot reports millimetres).
PLFLT CharHeightPx() {
  PLFLT default_mm = 0, height_mm = 0, page_x0 = 0, page_x1 = 1, page_y0 = 0, page_y1 = 1;
  plgchr(&default_mm, &height_mm);
  plgspa(&page_x0, &page_x1, &page_y0, &page_y1);
  return height_mm * kWidthPx / (page_x1 - page_x0);
}

// ---------------------------------------------------------------------------------------------------------
// Drawing. These functions run inside RenderGuarded: PLplot may leave them through longjmp, so they hold no
// objects with destructors (only numbers, plain arrays and pointers into the prepared scene).

void SetTextScale(PLFLT scale) { plschr(0.0, scale); }

// Approximate length of text in pixels at the current character height: PLplot's public API cannot measure
// text, so DejaVu Sans' mean advance for mixed text, about 0.73 character heights, is used (rounded up).
PLFLT TextLengthPx(const char* text) {
  int characters = 0;
  for (const char* c = text; *c; ++c) characters += (static_cast<unsigned char>(*c) & 0xC0) != 0x80;
  return 0.75 * CharHeightPx() * characters;
}

// Writes text centred along a viewport edge (plmtex), shrunk if needed to at most `max_px` pixels; the
// displacement from the edge, in character heights at `scale`, is kept.
void EdgeText(const char* side, PLFLT displacement, const char* text, PLFLT scale, PLFLT max_px) {
  SetTextScale(scale);
  const PLFLT length_px = TextLengthPx(text);
  const PLFLT fitted = length_px > max_px ? scale * max_px / length_px : scale;
  SetTextScale(fitted);
  plmtex(side, displacement * scale / fitted, 0.5, 0.5, text);
  SetTextScale(kTextScale);
}

// Text scale (relative to the current one) for a legend of `columns` columns whose line samples take
// `sample_fraction` of the viewport: at most `preferred`, smaller if PLplot's columns, each as wide as the
// longest entry plus sample and gaps, would not fit the viewport.
PLFLT LegendTextScale(const char* const* text, int count, int columns, PLFLT sample_fraction,
                      PLFLT viewport_px, PLFLT preferred) {
  PLFLT longest_px = 0;
  for (int i = 0; i < count; ++i) longest_px = std::max(longest_px, TextLengthPx(text[i]));
  const PLFLT available_px =
      0.95 * viewport_px / columns - sample_fraction * viewport_px - 2.5 * CharHeightPx();
  return std::min(preferred, available_px / longest_px);
}

// A filled dot of radius `radius_px` pixels at (x, y), for series of a single point; the window may scale x
// and y differently, so the dot is an ellipse in world coordinates.
void DrawDot(PLFLT x, PLFLT y, const Box& viewport, const Box& window, PLFLT radius_px) {
  const PLFLT a = radius_px * (window.x1 - window.x0) / ((viewport.x1 - viewport.x0) * kWidthPx);
  const PLFLT b = radius_px * (window.y1 - window.y0) / ((viewport.y1 - viewport.y0) * kHeightPx);
  plarc(x, y, a, b, 0.0, 360.0, 0.0, 1);
}

void DrawGrid(const Box& viewport, const Box& window, PLFLT x_tick) {
  plvpor(viewport.x0, viewport.x1, viewport.y0, viewport.y1);
  plwind(window.x0, window.x1, window.y0, window.y1);
  plcol0(kGrid);
  plwidth(1.0);
  plbox("g", x_tick, 0, "g", 0.0, 0);
}

void DrawAxes(const Box& viewport, PLFLT x_tick, PLFLT y_label_displacement, const char* x_label,
              const char* y_label, const char* title) {
  plcol0(kInk);
  plwidth(1.5);
  plbox("bcnst", x_tick, 0, "bcnstv", 0.0, 0);
  const PLFLT width_px = (viewport.x1 - viewport.x0) * kWidthPx,
              height_px = (viewport.y1 - viewport.y0) * kHeightPx;
  EdgeText("b", 3.0, x_label, kTextScale, width_px);
  EdgeText("l", y_label_displacement, y_label, kTextScale, height_px);
  EdgeText("t", 1.2, title, kTitleScale, width_px);
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

void DrawErrorPlot(const void* data) {
  const ErrorScene& s = *static_cast<const ErrorScene*>(data);

  // Layout: the y tick labels set the left margin.
  const PLFLT char_px = CharHeightPx();
  const PLFLT y_label_displacement = YLabelDisplacement(TickLabelCharacters(s.window.y0, s.window.y1));
  const Box viewport{(y_label_displacement + kLeftOfYLabel) * char_px / kWidthPx, 0.96, kViewportBottom,
                     kViewportTop};
  const PLFLT x_tick = XTickSpacing(viewport, s.window, char_px);
  DrawGrid(viewport, s.window, x_tick);

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

// ---------------------------------------------------------------------------------------------------------
// Rendering with PLplot

using DrawFunction = void (*)(const void* scene);

// PLplot keeps global state (current stream, handlers): one plot at a time.
std::mutex plplot_mutex;
// While a plot renders: where a fatal PLplot error jumps to, and PLplot's last error message.
std::jmp_buf* fatal_jump = nullptr;
PLINT plplot_error_code = 0;
char plplot_message[4096];

void RememberMessage(const char* message) {
  std::snprintf(plplot_message, sizeof(plplot_message), "%s", message ? message : "");
}

// plexit() calls exit() once its handler returns, so during a render the handler jumps back instead.
int OnPlplotExit(const char* message) {
  RememberMessage(message);
  if (fatal_jump) std::longjmp(*fatal_jump, 1);
  return 1;
}

// plabort() reports a failed call and carries on; the message is kept (plsError keeps it off stderr).
void OnPlplotAbort(const char* message) { RememberMessage(message); }

bool PngDeviceAvailable() {
  constexpr int kMaxDevices = 256;
  const char* menu[kMaxDevices + 1];
  const char* names[kMaxDevices + 1];
  const char** menu_ptr = menu;
  const char** names_ptr = names;
  int count = kMaxDevices;
  plgDevs(&menu_ptr, &names_ptr, &count);
  for (int i = 0; i < count; ++i)
    if (names[i] && std::strcmp(names[i], "pngcairo") == 0) return true;
  return false;
}

// Sets up colours, page and axis style of a new stream, before and after plinit.
void InitStream(std::FILE* file) {
  plsdev("pngcairo");
  plsfile(file);
  plspage(0.0, 0.0, kWidthPx, kHeightPx, 0, 0);
  PLINT r[kColours.size()], g[kColours.size()], b[kColours.size()];
  for (std::size_t i = 0; i < kColours.size(); ++i)
    r[i] = kColours[i][0], g[i] = kColours[i][1], b[i] = kColours[i][2];
  plscmap0(r, g, b, static_cast<PLINT>(kColours.size()));
  plscol0a(kBand, kColours[kBand][0], kColours[kBand][1], kColours[kBand][2], kBandAlpha);
  plinit();
  PLFLT position[kTurbo.size()], red[kTurbo.size()], green[kTurbo.size()], blue[kTurbo.size()];
  for (std::size_t i = 0; i < kTurbo.size(); ++i)
    position[i] = kTurbo[i][0], red[i] = kTurbo[i][1], green[i] = kTurbo[i][2], blue[i] = kTurbo[i][3];
  plscmap1n(256);
  plscmap1l(1, static_cast<PLINT>(kTurbo.size()), position, red, green, blue, nullptr);
  plsxax(kAxisDigits, 0);
  plsyax(kAxisDigits, 0);
  SetTextScale(kTextScale);
  pladv(0);
}

// Opens a fresh PLplot stream writing a pngcairo PNG to `file`, draws the scene and ends the stream; the file
// is closed either way. Returns false if PLplot failed (plplot_message says why). PLplot's fatal errors leave
// through longjmp, so no object with a destructor may live between here and PLplot: the scene is prepared
// beforehand and only plain values are touched after setjmp.
bool RenderGuarded(std::FILE* file, DrawFunction draw, const void* scene) {
  std::jmp_buf jump;
  fatal_jump = &jump;
  plplot_error_code = 0;
  plplot_message[0] = '\0';
  plsexit(OnPlplotExit);
  plsabort(OnPlplotAbort);
  plsError(&plplot_error_code, plplot_message);  // stream 0, current until plmkstrm: errors off stderr
  volatile bool file_given = false, ok = false;
  if (setjmp(jump) == 0) {
    if (!PngDeviceAvailable()) {
      if (plplot_message[0] == '\0')  // else PLplot's own message (say, no driver folder) tells more
        RememberMessage("PLplot has no pngcairo device (Debian package plplot-driver-cairo)");
    } else {
      PLINT stream = 0;
      plmkstrm(&stream);
      plsError(&plplot_error_code, plplot_message);
      file_given = true;  // plend1 closes it once plinit ran
      InitStream(file);
      draw(scene);
      plend1();
      ok = plplot_error_code == 0;
    }
  } else if (setjmp(jump) == 0) {
    // PLplot gave up part way: take the file back if plinit never ran, then release the stream (a second
    // failure lands in the branch above's else and ends here too).
    PLINT level = 0;
    plglevel(&level);
    if (file_given && level == 0) {
      plsfile(nullptr);
      file_given = false;
    }
    plend1();
  }
  if (!file_given) std::fclose(file);
  fatal_jump = nullptr;
  return ok;
}

bool IsPngFile(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return false;
  unsigned char signature[8] = {};
  const bool ok =
      std::fread(signature, 1, 8, file) == 8 && std::memcmp(signature, "\x89PNG\r\n\x1a\n", 8) == 0;
  std::fclose(file);
  return ok;
}

// Renders to "<png_path>.tmp<pid>" and renames it onto png_path once PLplot finished without error.
Status WritePng(const std::string& png_path, DrawFunction draw, const void* scene) {
  if (png_path.empty()) return Status::Error("plot: the PNG path is empty");
  const std::string tmp_path = png_path + ".tmp" + std::to_string(::getpid());
  std::FILE* file = std::fopen(tmp_path.c_str(), "wb");
  if (!file)
    return Status::Error("plot " + png_path + ": cannot write " + tmp_path + ": " + std::strerror(errno));
  bool rendered = false;
  std::string message;
  {
    std::lock_guard<std::mutex> lock(plplot_mutex);
    rendered = RenderGuarded(file, draw, scene);
    message = plplot_message;
  }
  // PLplot's messages come with newlines and ", aborting operation".
  message.erase(0, message.find_first_not_of(" \n"));
  message.erase(message.find_last_not_of(" \n") + 1);
  std::error_code ignored;
  if (!rendered || !IsPngFile(tmp_path)) {
    std::filesystem::remove(tmp_path, ignored);
    return Status::Error("plot " + png_path + ": PLplot did not write the PNG" +
                         (message.empty() ? std::string() : " (" + message + ")"));
  }
  std::error_code error;
  std::filesystem::rename(tmp_path, png_path, error);
  if (error) {
    std::filesystem::remove(tmp_path, ignored);
    return Status::Error("plot " + png_path + ": cannot rename " + tmp_path + ": " + error.message());
  }
  return Status();
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------

Status WriteTopViewPlot(const std::string& png_path, const std::vector<Eigen::Vector3d>& reference,
                        const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& error,
                        const std::string& title, const std::string& error_label) {
  // Check the input.
  if (reference.empty()) return Status::Error("plot " + png_path + ": the reference trajectory is empty");
  if (estimate.empty()) return Status::Error("plot " + png_path + ": the estimated trajectory is empty");
  if (error.size() != estimate.size())
    return Status::Error("plot " + png_path + ": " + std::to_string(error.size()) + " error values for " +
                         std::to_string(estimate.size()) + " estimated poses");
  if (Status s = CheckPlottable(png_path, "reference", reference); !s.ok()) return s;
  if (Status s = CheckPlottable(png_path, "estimate", estimate); !s.ok()) return s;
  if (Status s = CheckPlottable(png_path, "error", error, kMaxValue); !s.ok()) return s;

  // Prepare the scene: coordinates, their bounding box, segment colours, text.
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

  // Render.
  return WritePng(png_path, DrawTopView, &scene);
}

Status WriteErrorPlot(const std::string& png_path, const std::vector<double>& seconds,
                      const std::vector<double>& error, const ErrorStats& stats, const std::string& title,
                      const std::string& x_label, const std::string& y_label) {
  // Check the input.
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

  // Prepare the scene: time from the first stamp, a window with room for the legend at the top, text.
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

  // Render.
  return WritePng(png_path, DrawErrorPlot, &scene);
}

}  // namespace uf
