// Must NOT compile (types_no_csv_codec_fails_to_compile): a registered type that is not a record
// and has no CsvCodec specialisation cannot be registered, and the compiler says what to do.

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

// A Lua codec exists, so the CSV one is the only thing missing.
template <>
struct cobra::script::LuaCodec<Opaque> {
  static std::string_view form() { return "a number"; }
  static void read(lua_State*, int, Opaque&) {}
  static void push(lua_State*, const Opaque&) {}
};

void registerOpaque() { cobra::types::registerType<Opaque>(); }
