#pragma once
/// @file
/// Numbers in error messages, as printf's %g: "0.25", "1e-06", "1.5e+06" (short, unit-free; the
/// caller appends the unit).

#include <cstdio>
#include <string>

namespace cobra::text {

/// `value` with at most `significant_digits` significant digits (printf's "%.*g"; 6 is plain %g).
inline std::string number(double value, int significant_digits = 6) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return text;
}

}  // namespace cobra::text
