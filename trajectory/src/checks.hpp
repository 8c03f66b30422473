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

/// `what...` names the value, e.g. "Conditions: ", "final velocity"; the message is only built on
/// failure, so a passing check allocates nothing (Polynomial::stop is real-time safe).
template <class... What>
void requireFinite(double value, const What&... what) {
  if (!std::isfinite(value)) fail(what..., " is ", value, ", expected a finite number");
}

/// A duration-like quantity: finite and > 0; `unit` follows the value in the message ("s", "m/s").
template <class... What>
void requirePositive(double value, const char* unit, const What&... what) {
  if (!std::isfinite(value) || !(value > 0.0)) fail(what..., " is ", value, " ", unit, ", expected a finite value > 0");
}

}  // namespace cobra::trajectory::detail
