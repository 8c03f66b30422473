#pragma once
// What the text-format fuzzers share: exact printing of numbers (so that a printed value parses
// back to the same double) and the check that an error message names its source and line.

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include <kdl/frames.hpp>

namespace cobra::fuzz {

/// The shortest decimal form that parses back to exactly `value` (std::to_chars).
inline std::string exact(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

/// X,Y,Z with exact() numbers.
inline std::string exactVector(const KDL::Vector& v) {
  return exact(v.x()) + "," + exact(v.y()) + "," + exact(v.z());
}

/// Exactly equal (KDL's operator== on vectors allows 1e-6: KDL_USE_EQUAL).
inline bool identical(const KDL::Vector& a, const KDL::Vector& b) {
  return a.x() == b.x() && a.y() == b.y() && a.z() == b.z();
}

/// Positions exactly, rotations within 1e-9 (a text form that prints them as roll, pitch, yaw
/// gives them back only to rounding).
inline bool sameFrame(const KDL::Frame& a, const KDL::Frame& b) { return identical(a.p, b.p) && KDL::Equal(a.M, b.M, 1e-9); }

/// Prints why the property failed and aborts (libFuzzer saves the input).
[[noreturn]] inline void fail(std::string_view why, std::string_view detail) {
  std::fprintf(stderr, "fuzz: %.*s: %.*s\n", static_cast<int>(why.size()), why.data(), static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

/// Aborts unless `message` reads "SOURCE: ..." or "SOURCE:LINE: ..." with LINE a line of `text`
/// (1 to the number of lines; a text without a final newline still has its last line).
inline void requireLocated(std::string_view message, std::string_view source, std::string_view text) {
  if (message.substr(0, source.size()) != source || message.substr(source.size(), 1) != ":")
    fail("error does not name the source", message);
  const std::string_view rest = message.substr(source.size() + 1);
  if (rest.empty() || rest[0] < '0' || rest[0] > '9') return;  // about the whole text ("SOURCE: no ...")
  std::size_t line = 0;
  const auto [end, error] = std::from_chars(rest.data(), rest.data() + rest.size(), line);
  if (error != std::errc() || end == rest.data() + rest.size() || *end != ':') fail("malformed SOURCE:LINE", message);
  const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  if (line < 1 || line > lines) fail("error names a line the text does not have", message);
}

}  // namespace cobra::fuzz
