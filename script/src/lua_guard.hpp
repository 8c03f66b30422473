#pragma once
// The rules that keep C++ and Lua's longjmp-based errors apart (internal to cobra::script).
//
// Debian's liblua is C: lua_error longjmps. Jumping over a C++ frame that holds an object with
// a destructor skips that destructor, and jumping out of a catch block corrupts the exception
// state. So a C function called by Lua is split in two:
//  - an *impl* in C++ that may throw C++ exceptions, and calls only Lua functions that cannot
//    raise (type tests, raw gets on existing keys, pushing numbers/booleans/light userdata,
//    lua_next), or raising ones only through `protectedCall` (which turns a Lua error into a
//    C++ exception);
//  - `guarded<impl>`, the function Lua sees: it catches the exception, copies its message to a
//    stack buffer, leaves the catch block and only then raises the Lua error (with file:line).

#include <cstring>
#include <exception>
#include <string>
#include <string_view>

#include <lua.hpp>

#include "cobra/core/error.hpp"
#include "cobra/script/lua_state.hpp"

namespace cobra::script::detail {

/// Longest error message passed from C++ to Lua; longer ones are cut with "...".
inline constexpr std::size_t kMessageBytes = 4096;

inline void copyMessage(char (&buffer)[kMessageBytes], const char* text) {
  const std::size_t n = std::strlen(text);
  if (n < kMessageBytes) {
    std::memcpy(buffer, text, n + 1);
  } else {
    std::memcpy(buffer, text, kMessageBytes - 4);
    std::memcpy(buffer + kMessageBytes - 4, "...", 4);
  }
}

template <int (*Impl)(lua_State*)>
int guarded(lua_State* L) {
  char message[kMessageBytes];
  try {
    return Impl(L);
  } catch (const std::exception& e) {
    copyMessage(message, e.what());
  } catch (...) {
    copyMessage(message, "unknown C++ exception");
  }
  luaL_where(L, 1);  // "file.lua:12: " of the Lua code that called us
  lua_pushstring(L, message);
  lua_concat(L, 2);
  return lua_error(L);
}

/// Runs `thunk(L)` with the light userdata `data` as its only argument in protected mode,
/// leaving its `results` results on the stack. A Lua error (e.g. pool exhaustion) becomes a
/// cobra::core::Error with the state's message. The thunk must hold no C++ object with a
/// destructor and throw nothing.
inline void protectedCall(lua_State* L, lua_CFunction thunk, const void* data, int results) {
  lua_pushcfunction(L, thunk);
  lua_pushlightuserdata(L, const_cast<void*>(data));
  const int status = lua_pcall(L, 1, results, 0);
  if (status == LUA_OK) return;
  LuaState* owner = LuaState::from(L);
  if (owner != nullptr) throw core::Error(owner->popError(status, L));
  const std::string message = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "Lua error";
  lua_pop(L, 1);
  throw core::Error(message);
}

/// Pushes a copy of `text` (protected: may throw cobra::core::Error on pool exhaustion).
inline void pushString(lua_State* L, std::string_view text) {
  protectedCall(
      L,
      [](lua_State* S) -> int {
        const auto* view = static_cast<const std::string_view*>(lua_touserdata(S, 1));
        lua_pushlstring(S, view->data(), view->size());
        return 1;
      },
      &text, 1);
}

/// Pushes t[key] for the table at `index` without raising (no metamethods, no new strings):
/// scans the table with lua_next. Pushes nil when absent. For small records ({x=, y=, z=}).
inline void rawField(lua_State* L, int index, std::string_view key) {
  index = lua_absindex(L, index);
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING) {
      std::size_t n = 0;
      const char* k = lua_tolstring(L, -2, &n);
      if (std::string_view(k, n) == key) {
        lua_remove(L, -2);  // keep the value only
        return;
      }
    }
    lua_pop(L, 1);
  }
  lua_pushnil(L);
}

}  // namespace cobra::script::detail
