#pragma once
// Construction-time argument checks shared by the TGL sources: each throws std::invalid_argument
// with a message that names the element, its value and what was expected.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace cobra::trajectory::detail {

/// Concatenates the streamable `parts` into one message.
template <class... Parts>
std::string message(const Parts&... parts) {
  std::ostringstream text;
  (text << ... << parts);
  return text.str();
}

template <class... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  throw std::invalid_argument(message(parts...));
}

/// `what` names the value, e.g. "Conditions: final velocity".
inline void requireFinite(double value, const std::string& what) {
  if (!std::isfinite(value)) fail(what, " is ", value, ", expected a finite number");
}

/// A duration-like quantity: finite and > 0. `unit` is appended to the value ("s", "m/s").
inline void requirePositive(double value, const std::string& what, const char* unit) {
  if (!std::isfinite(value) || !(value > 0.0))
    fail(what, " is ", value, " ", unit, ", expected a finite value > 0");
}

}  // namespace cobra::trajectory::detail
