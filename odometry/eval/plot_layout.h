// Internal to odometry/eval (the PNG plots of plots.h); not to be included from elsewhere.
// Layout arithmetic of the plots: data windows, tick spacing and margins. Nothing here calls PLplot.
#pragma once

#include <plplot.h>

namespace uf::plot {

// A rectangle in world (data) or normalized coordinates.
struct Box {
  double x0, x1, y0, y1;
};

// Widens a value range whose ends are (nearly) equal: to [0, 1] at zero, else by 5% of the value each side.
void WidenIfFlat(double& lo, double& hi);

// The world window for `data` drawn with equal axis scaling (one metre as long in x as in y) into
// `viewport` (normalized page coordinates), leaving its top `legend_fraction` free for a legend.
Box EqualScaleWindow(Box data, const Box& viewport, double legend_fraction);

// Characters of the longest tick label on an axis spanning [lo, hi] (over-estimated).
int TickLabelCharacters(double lo, double hi);

// Spacing of the x ticks in world units, so that tick labels `char_px` pixels high do not crowd.
PLFLT XTickSpacing(const Box& viewport, const Box& window, PLFLT char_px);

// Horizontal layout, in character heights: the y label's distance from the left axis so that it clears tick
// labels of `characters` digits, and the width left of the y label.
PLFLT YLabelDisplacement(int characters);
constexpr PLFLT kLeftOfYLabel = 0.9;

// The colour bar right of the viewport, in character heights: its gap from the viewport, its width, and the
// whole right margin it takes with tick labels of `characters` digits and its label.
constexpr PLFLT kBarGap = 1.0, kBarWidth = 1.5;
PLFLT ColourBarMargin(int characters);

}  // namespace uf::plot
