// Must NOT compile (types_no_csv_codec_fails_to_compile): a registered type that is not a record
// and has no CsvCodec specialisation cannot be registered, and the compiler says what to do.

#include "opaque.hpp"

// A Lua codec exists, so the CSV one is the only thing missing.
template <>
struct cobra::script::LuaCodec<Opaque> {
  static std::string_view form() { return "a number"; }
  static void read(lua_State*, int, Opaque&) {}
  static void push(lua_State*, const Opaque&) {}
};

void registerOpaque() { cobra::types::registerType<Opaque>(); }
