// Internal to odometry/eval (the PNG plots of plots.h); not to be included from elsewhere.
// A PLplot session that renders one plot to a PNG file, with PLplot's fatal errors caught.
#pragma once

#include <string>

#include "odometry/types/status.h"

namespace uf::plot {

// Draws a prepared scene onto the current PLplot stream. It runs inside the guarded render, which PLplot's
// fatal errors leave through longjmp: it must hold no objects with destructors (only numbers, plain arrays
// and pointers into the scene), so the scene is prepared before WritePng.
using DrawFunction = void (*)(const void* scene);

// Renders `scene` with `draw` on a fresh 1280x960 pngcairo stream (white page, the colours of plot_style.h,
// kTextScale text) to "<png_path>.tmp<pid>" and renames it onto png_path once PLplot finished without error.
// On failure nothing is left behind and the error names png_path and PLplot's message. Plots render one at a
// time (PLplot keeps global state); nothing is printed and the process never exits.
Status WritePng(const std::string& png_path, DrawFunction draw, const void* scene);

}  // namespace uf::plot
