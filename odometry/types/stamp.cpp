#include "stamp.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace uf {

Stamp FromSeconds(double seconds) { return static_cast<Stamp>(std::llround(seconds * 1e9)); }

std::optional<Stamp> ParseSeconds(std::string_view text) {
  // sign, integer digits, optional fraction, optional exponent; the value is (digits) * 10^(exponent - 9)
  // nanoseconds kept as an exact integer mantissa and a power of ten, then rounded half away from zero.
  size_t i = 0;
  const size_t n = text.size();
  bool negative = false;
  if (i < n && (text[i] == '+' || text[i] == '-')) negative = text[i++] == '-';
  unsigned __int128 mantissa = 0;
  int digits = 0, significant = 0, exponent = 0;
  // Digits beyond 30 significant ones are below 1e-21 of the value: they are dropped.
  auto take_digit = [&](char c, bool fractional) {
    ++digits;
    if (significant == 0 && c == '0') {
      if (fractional) --exponent;
      return;
    }
    if (significant < 30) {
      mantissa = mantissa * 10 + static_cast<unsigned>(c - '0');
      ++significant;
      if (fractional) --exponent;
    } else if (!fractional) {
      ++exponent;
    }
  };
  while (i < n && text[i] >= '0' && text[i] <= '9') take_digit(text[i++], false);
  if (i < n && text[i] == '.') {
    ++i;
    while (i < n && text[i] >= '0' && text[i] <= '9') take_digit(text[i++], true);
  }
  if (digits == 0) return std::nullopt;
  if (i < n && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool exp_negative = false;
    if (i < n && (text[i] == '+' || text[i] == '-')) exp_negative = text[i++] == '-';
    if (i == n) return std::nullopt;
    int e = 0;
    while (i < n && text[i] >= '0' && text[i] <= '9') {
      if (e < 100000) e = e * 10 + (text[i] - '0');
      ++i;
    }
    exponent += exp_negative ? -e : e;
  }
  if (i != n) return std::nullopt;

  int shift = exponent + 9;  // value in ns = mantissa * 10^shift
  constexpr unsigned __int128 kLimit = static_cast<unsigned __int128>(INT64_MAX);
  if (mantissa == 0) return Stamp{0};
  while (shift > 0) {
    if (mantissa > kLimit) return std::nullopt;
    mantissa *= 10;
    --shift;
  }
  bool round_up = false;  // half away from zero, decided by the first dropped digit
  while (shift < 0) {
    const unsigned last = static_cast<unsigned>(mantissa % 10);
    mantissa /= 10;
    ++shift;
    if (shift == 0) round_up = last >= 5;
  }
  if (round_up) ++mantissa;
  if (mantissa > kLimit) return std::nullopt;
  const Stamp value = static_cast<Stamp>(mantissa);
  return negative ? -value : value;
}

std::string StampText(Stamp t) { return std::to_string(ToSeconds(t)) + " s"; }

std::string FormatSeconds(Stamp t) {
  const bool negative = t < 0;
  // -(t + 1) + 1 avoids overflowing on INT64_MIN.
  const unsigned long long magnitude =
      negative ? static_cast<unsigned long long>(-(t + 1)) + 1ULL : static_cast<unsigned long long>(t);
  char text[32];
  std::snprintf(text, sizeof(text), "%s%llu.%09llu", negative ? "-" : "", magnitude / kNanosecondsPerSecond,
                magnitude % kNanosecondsPerSecond);
  return text;
}

}  // namespace uf
