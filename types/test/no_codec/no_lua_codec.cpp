// Must NOT compile (types_no_lua_codec_fails_to_compile): a registered type that is not a record
// and has no LuaCodec specialisation cannot be registered, and the compiler says what to do.

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

// A CSV codec exists, so the Lua one is the only thing missing.
template <>
struct cobra::components::CsvCodec<Opaque> : cobra::components::TextCsvCodec<Opaque> {};

void registerOpaque() { cobra::types::registerType<Opaque>(); }
