#include "odometry/eval/plot_layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "odometry/eval/plot_style.h"

namespace uf::plot {
namespace {

// Grows [lo, hi] about its middle so that a degenerate range still spans `min_span`.
void EnsureSpan(double& lo, double& hi, double min_span) {
  if (hi - lo >= min_span) return;
  const double mid = 0.5 * (lo + hi);
  lo = mid - 0.5 * min_span;
  hi = mid + 0.5 * min_span;
}

// Width of a tick label character in character heights (PLplot's unit of text size), measured for DejaVu
// Sans digits drawn by the pngcairo device.
constexpr PLFLT kDigitWidth = 0.85;

}  // namespace

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

// The data box (padded by 5%) must fit the viewport below its top `legend_fraction`: metres per pixel =
// max(span_x / w_px, span_y / (h_px (1 - legend_fraction))). The data are centred in that area and the axis
// with room to spare is widened.
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

// PLplot puts 3 to 10 ticks on an axis and writes as many decimals as the tick spacing needs (at most
// span / 10), so both ends are written with the decimals of span / 10.
int TickLabelCharacters(double lo, double hi) {
  const double span = hi > lo ? hi - lo : std::max({std::abs(lo), std::abs(hi), 1.0});
  const int decimals = std::clamp(-static_cast<int>(std::floor(std::log10(span / 10))), 0, 15);
  char buffer[64];
  return std::max(std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, lo),
                  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, hi));
}

// PLplot's own choice ignores the label width. This is the smallest 1, 2 or 5 x 10^k that gives at most 6
// ticks and leaves 1.5 label widths per tick.
PLFLT XTickSpacing(const Box& viewport, const Box& window, PLFLT char_px) {
  const double span = window.x1 - window.x0;
  const double label_px = kDigitWidth * char_px * TickLabelCharacters(window.x0, window.x1);
  const double ticks = std::clamp((viewport.x1 - viewport.x0) * kWidthPx / (1.5 * label_px), 1.0, 6.0);
  const double decade = std::pow(10.0, std::floor(std::log10(span / ticks)));
  for (double multiple : {1.0, 2.0, 5.0})
    if (multiple * decade >= span / ticks) return multiple * decade;
  return 10.0 * decade;
}

PLFLT YLabelDisplacement(int characters) { return 1.9 + kDigitWidth * characters; }

// Gap, bar, tick labels (0.8 + their digits), then 3.0 for the gap, the label and the page edge.
PLFLT ColourBarMargin(int characters) { return kBarGap + kBarWidth + 0.8 + kDigitWidth * characters + 3.0; }

}  // namespace uf::plot
