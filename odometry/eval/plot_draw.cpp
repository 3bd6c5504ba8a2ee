#include "odometry/eval/plot_draw.h"

#include <algorithm>

#include "odometry/eval/plot_style.h"

namespace uf::plot {
namespace {

// Approximate length of text in pixels at the current character height: PLplot's public API cannot measure
// text, so DejaVu Sans' mean advance for mixed text, about 0.73 character heights, is used (rounded up).
// UTF-8 continuation bytes (10xxxxxx) are not counted, so each character counts once.
PLFLT TextLengthPx(const char* text) {
  int characters = 0;
  for (const char* c = text; *c; ++c) characters += (static_cast<unsigned char>(*c) & 0xC0) != 0x80;
  return 0.75 * CharHeightPx() * characters;
}

}  // namespace

void SetTextScale(PLFLT scale) { plschr(0.0, scale); }

// PLplot reports the character height in millimetres; the page's width in millimetres converts it.
PLFLT CharHeightPx() {
  PLFLT default_mm = 0, height_mm = 0, page_x0 = 0, page_x1 = 1, page_y0 = 0, page_y1 = 1;
  plgchr(&default_mm, &height_mm);
  plgspa(&page_x0, &page_x1, &page_y0, &page_y1);
  return height_mm * kWidthPx / (page_x1 - page_x0);
}

// plmtex measures the displacement in character heights at the current size, so it is scaled by
// scale / fitted to stay where it would be at `scale`.
void EdgeText(const char* side, PLFLT displacement, const char* text, PLFLT scale, PLFLT max_px) {
  SetTextScale(scale);
  const PLFLT length_px = TextLengthPx(text);
  const PLFLT fitted = length_px > max_px ? scale * max_px / length_px : scale;
  SetTextScale(fitted);
  plmtex(side, displacement * scale / fitted, 0.5, 0.5, text);
  SetTextScale(kTextScale);
}

// PLplot makes all columns as wide as the longest entry plus the line sample and gaps (taken as 2.5 character
// heights); the columns must fit 95% of the viewport.
PLFLT LegendTextScale(const char* const* text, int count, int columns, PLFLT sample_fraction,
                      PLFLT viewport_px, PLFLT preferred) {
  PLFLT longest_px = 0;
  for (int i = 0; i < count; ++i) longest_px = std::max(longest_px, TextLengthPx(text[i]));
  const PLFLT available_px =
      0.95 * viewport_px / columns - sample_fraction * viewport_px - 2.5 * CharHeightPx();
  return std::min(preferred, available_px / longest_px);
}

// The window may scale x and y differently, so the dot is an ellipse in world coordinates, with semi-axes
// of radius_px times the world units per pixel in x and in y.
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

TimePlotFrame BeginTimePlot(const Box& window, PLFLT bottom, PLFLT top) {
  const PLFLT char_px = CharHeightPx();
  TimePlotFrame frame;
  frame.y_label_displacement = YLabelDisplacement(TickLabelCharacters(window.y0, window.y1));
  frame.viewport = {(frame.y_label_displacement + kLeftOfYLabel) * char_px / kWidthPx, 0.96, bottom, top};
  frame.x_tick = XTickSpacing(frame.viewport, window, char_px);
  DrawGrid(frame.viewport, window, frame.x_tick);
  return frame;
}

// The axis labels may be as long as their edge of the viewport, the title as wide as the viewport.
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

}  // namespace uf::plot
