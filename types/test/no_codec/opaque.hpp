#pragma once
// The type of the must-not-compile cases here: registered for ports (DataTypeTraits), not a
// record; each case gives it every codec but one, then registers it (after the codec: a
// specialisation must precede the registration's use of it).

#include "cobra/types/register_type.hpp"

namespace {
struct Opaque {
  double value = 0.0;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<Opaque> {
  static constexpr std::string_view name = "test.Opaque";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "a number";
  static std::string print(const Opaque& v) { return std::to_string(v.value); }
  static bool parse(std::string_view, Opaque&) { return false; }
};
