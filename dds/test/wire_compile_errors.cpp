// Compiled only by the test dds_wire_compile_errors (never part of a build): each case must fail
// to compile with cobra's static_assert message saying what to do. WIRE_CASE selects the case.
#include <string>
#include <string_view>
#include <tuple>

#include "cobra/dds/register_type.hpp"

namespace {
struct Celsius {  // a registered cobra type that is no record, without a DdsCodec
  double value = 0.0;
};
struct NoPackage {  // a record whose name has no package
  double depth = 0.0;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<Celsius> {
  static constexpr std::string_view name = "Celsius";
  static constexpr cobra::core::DataKind kind = cobra::core::DataKind::Pure;
  static constexpr std::string_view format = "a number";
  static std::string print(const Celsius&) { return "0"; }
  static bool parse(std::string_view, Celsius&) { return true; }
};

template <>
struct cobra::core::DataTypeTraits<NoPackage> : cobra::core::RecordTraits<NoPackage> {
  static constexpr std::string_view name = "NoPackage";
  static constexpr auto fields = std::tuple{field("depth", &NoPackage::depth, "m")};
};

#if WIRE_CASE == 1
void registerCelsius() { cobra::dds::registerDdsType<Celsius>(); }
#elif WIRE_CASE == 2
void registerNoPackage() { cobra::dds::registerDdsType<NoPackage>(); }
#endif
