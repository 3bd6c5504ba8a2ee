// Internal to odometry/eval (the PNG plots of plots.h); not to be included from elsewhere.
// The look shared by every plot: page size, colours and the base text size.
#pragma once

#include <plplot.h>

#include <array>

namespace uf::plot {

// The PNG page in pixels.
constexpr PLINT kWidthPx = 1280, kHeightPx = 960;

// Colour map 0 (PLplot's indexed colours); index 0 is the page background. kColours below is in this order.
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
inline constexpr std::array<std::array<PLINT, 3>, 10> kColours{{
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

// Colour map 1 (error -> colour): Google's Turbo, sampled at 9 points and interpolated linearly in RGB.
// Each row is {position in [0, 1], red, green, blue}.
inline constexpr std::array<std::array<PLFLT, 4>, 9> kTurbo{{
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

// Tick labels keep this many digits before PLplot adds "(x10^k)".
constexpr PLINT kAxisDigits = 12;

}  // namespace uf::plot
