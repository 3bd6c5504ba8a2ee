// Fast per-pixel maths of the camera renderer: the sRGB transfer curve to 8-bit digital numbers through a
// lookup table, and standard normal samples from 16 random bits through an inverse-CDF table.
#pragma once

#include <cstdint>

namespace uf::sim {

inline constexpr int kSrgbTableSteps = 4096;

// The shared tables (built once, thread-safe): SrgbDnTable() has kSrgbTableSteps + 2 entries,
// StandardNormalTable() 65536. Hoist the pointers out of pixel loops.
const float* SrgbDnTable();
const float* StandardNormalTable();

// sRGB encoding of a linear value in [0, 1] (clamped; NaN gives 0), scaled to 8-bit DN in [0, 255] and not
// rounded:
//   srgb(x) = 12.92 x                      for x <= 0.0031308
//           = 1.055 x^(1/2.4) - 0.055      otherwise,
// tabulated at kSrgbTableSteps steps and linearly interpolated (error < 0.01 DN). table = SrgbDnTable().
inline float LinearToSrgbDn(const float* table, float linear) {
  const float s = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) * kSrgbTableSteps : 0.0f;
  const int i = static_cast<int>(s);
  const float f = s - static_cast<float>(i);
  return table[i] + f * (table[i + 1] - table[i]);
}

// A standard normal sample from 16 uniformly random bits: the table (StandardNormalTable()) holds
// Phi^-1((i + 0.5) / 65536) for i in [0, 65536), rescaled to unit variance, so samples are N(0, 1)
// truncated at about 4.3 sigma.
inline float StandardNormalFromBits(const float* table, std::uint16_t bits) { return table[bits]; }

}  // namespace uf::sim
