#include "odometry/eval/plot_input.h"

#include <cmath>
#include <cstdio>

namespace uf::plot {
namespace {

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

}  // namespace

std::string FormatValue(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}

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

}  // namespace uf::plot
