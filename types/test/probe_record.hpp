#pragma once
// A record registered by register_type_dds_test.cpp and register_without_dds.cpp, the same
// definition in both translation units.
#include <string_view>
#include <tuple>

#include "cobra/core/record.hpp"

namespace types_test {
struct Probe {
  double depth = 0.0;  // m
  double force = 0.0;  // N
};
/// registerType<Probe> as compiled without the dds headers (register_without_dds.cpp): its address,
/// so that the caller runs that translation unit's definition, not one inlined into its own.
using Registration = void (*)();
Registration probeRegistrationWithoutDds();
}  // namespace types_test

template <>
struct cobra::core::DataTypeTraits<types_test::Probe> : cobra::core::RecordTraits<types_test::Probe> {
  static constexpr std::string_view name = "types_test.Probe";
  static constexpr auto fields = std::tuple{field("depth", &types_test::Probe::depth, "m", "insertion depth"),
                                            field("force", &types_test::Probe::force, "N", "axial force")};
};
