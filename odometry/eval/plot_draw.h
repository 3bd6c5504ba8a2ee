// Internal to odometry/eval (the PNG plots of plots.h); not to be included from elsewhere.
// PLplot drawing helpers shared by the plots: text size and placement, grid, axes, dots.
// They run inside a guarded render (plot_png.h): PLplot may leave them through longjmp, so they hold no
// objects with destructors (only numbers, plain arrays and pointers).
#pragma once

#include <plplot.h>

#include "odometry/eval/plot_layout.h"

namespace uf::plot {

// Sets the text size relative to PLplot's default character height.
void SetTextScale(PLFLT scale);

// Height of a character at the current text size, in pixels.
PLFLT CharHeightPx();

// Writes text centred along a viewport edge (plmtex `side`: "b", "l", "t", ...), shrunk if needed to at most
// `max_px` pixels; the displacement from the edge, in character heights at `scale`, is kept. The text size is
// kTextScale afterwards.
void EdgeText(const char* side, PLFLT displacement, const char* text, PLFLT scale, PLFLT max_px);

// Text scale (relative to the current one) for a legend of `count` entries `text` in `columns` columns whose
// line samples take `sample_fraction` of the viewport, `viewport_px` pixels wide: at most `preferred`,
// smaller if the columns would not fit.
PLFLT LegendTextScale(const char* const* text, int count, int columns, PLFLT sample_fraction,
                      PLFLT viewport_px, PLFLT preferred);

// A filled dot of radius `radius_px` pixels at world (x, y), in the current colour; for series of a single
// point, which a line cannot show.
void DrawDot(PLFLT x, PLFLT y, const Box& viewport, const Box& window, PLFLT radius_px);

// Sets up `viewport` (normalized page coordinates) showing `window` (world coordinates) and draws the grid,
// with vertical lines every `x_tick` and PLplot's own horizontal spacing.
void DrawGrid(const Box& viewport, const Box& window, PLFLT x_tick);

// The frame of a plot over time: a viewport from `bottom` to `top` (normalized page coordinates) whose left
// margin fits the y tick labels of `window` and the y label, its x tick spacing and the y label's
// displacement. BeginTimePlot sets it up and draws the grid (DrawGrid).
struct TimePlotFrame {
  Box viewport;
  PLFLT x_tick, y_label_displacement;
};
TimePlotFrame BeginTimePlot(const Box& window, PLFLT bottom, PLFLT top);

// Draws the frame with ticks and tick labels, the axis labels (the y label `y_label_displacement` character
// heights left of the axis) and the title, over what DrawGrid set up.
void DrawAxes(const Box& viewport, PLFLT x_tick, PLFLT y_label_displacement, const char* x_label,
              const char* y_label, const char* title);

}  // namespace uf::plot
