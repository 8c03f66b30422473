// Must NOT compile (types_no_lua_codec_fails_to_compile): a registered type that is not a record
// and has no LuaCodec specialisation cannot be registered, and the compiler says what to do.

#include "opaque.hpp"

// A CSV codec exists, so the Lua one is the only thing missing.
template <>
struct cobra::components::CsvCodec<Opaque> : cobra::components::TextCsvCodec<Opaque> {};

void registerOpaque() { cobra::types::registerType<Opaque>(); }
