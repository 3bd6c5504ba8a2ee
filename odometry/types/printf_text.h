// printf-style formatting of numbers into a std::string, for messages and reports that print them with a
// chosen precision ("%.2f m", "%g"). Every argument is passed as a double, so the conversions are %f, %e and
// %g (counts included: "%.0f"). The result is cut at 255 characters.
#pragma once

#include <cstdio>
#include <string>

namespace uf {

template <typename... Numbers>
std::string PrintfText(const char* format, Numbers... numbers) {
  char text[256];
  std::snprintf(text, sizeof text, format, static_cast<double>(numbers)...);
  return text;
}

}  // namespace uf
