// Time inside ultrafusion is an int64 count of nanoseconds (since the epoch, or since the start of a dataset
// when the source has relative times). Seconds as double appear only at file boundaries.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace uf {

using Stamp = std::int64_t;

constexpr Stamp kNanosecondsPerSecond = 1'000'000'000;

// The double nearest to t / 1e9 (through long double, exact for |t| < 2^64), i.e. what parsing the decimal
// text of the stamp as a float64 gives.
constexpr double ToSeconds(Stamp t) { return static_cast<double>(static_cast<long double>(t) / 1e9L); }

// Nearest nanosecond; callers check that |seconds| < ~9.2e9 (the int64 range).
Stamp FromSeconds(double seconds);

// Parses a decimal number of seconds ("1305031102.160407", "1.037359e-01", "-0.5") exactly to the nearest
// nanosecond, without going through a double, so stamps written with nanosecond digits survive a round trip.
// Returns nullopt for anything that is not a finite decimal number in range.
std::optional<Stamp> ParseSeconds(std::string_view text);

// "1305031102.160407000": seconds with exactly nine decimals, the inverse of ParseSeconds.
std::string FormatSeconds(Stamp t);

// "1305031102.160407 s": seconds with six decimals and the unit, for messages.
std::string StampText(Stamp t);

}  // namespace uf
