#pragma once
/// @file
/// Configure-time error type of the runtime. Real-time paths never throw; they return a status.

#include <stdexcept>
#include <string>

namespace cobra::core {

/// Thrown by configure-time calls (connecting ports, setting properties by name, calling
/// operations by name) on misuse. The message names the component, the element and what was
/// expected, so it can be shown to the user as it is.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace cobra::core
