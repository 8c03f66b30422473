#include "cobra/deploy/lua_configuration.hpp"

#include <lua.hpp>

#include <algorithm>
#include <cstdio>
#include <map>

#include "cobra/core/error.hpp"
#include "cobra/script/lua_state.hpp"
#include "configuration_table.hpp"

namespace cobra::deploy {

bool luaValueText(lua_State* L, int index, std::string& out) {
  switch (lua_type(L, index)) {
    case LUA_TBOOLEAN: out = lua_toboolean(L, index) ? "true" : "false"; return true;
    case LUA_TSTRING: out = lua_tostring(L, index); return true;
    case LUA_TNUMBER: {
      char buffer[64];
      if (lua_isinteger(L, index)) std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(lua_tointeger(L, index)));
      else std::snprintf(buffer, sizeof buffer, "%.17g", lua_tonumber(L, index));
      out = buffer;
      return true;
    }
    case LUA_TTABLE: {
      const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, index));
      out = "[";
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, index, i);
        std::string element;
        const bool ok = lua_type(L, -1) == LUA_TNUMBER && luaValueText(L, lua_gettop(L), element);
        lua_pop(L, 1);
        if (!ok) return false;
        out += (i > 1 ? ", " : "") + element;
      }
      out += "]";
      return true;
    }
    default: return false;
  }
}

namespace {

/// The string keys of the table at `index`, sorted (Lua's own order is not reproducible).
std::vector<std::string> sortedKeys(lua_State* L, int index, const std::string& where) {
  std::vector<std::string> keys;
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING) {
      lua_pop(L, 1);
      throw core::Error(where + ": keys must be names (component or property names)");
    }
    keys.emplace_back(lua_tostring(L, -1));
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

}  // namespace

namespace detail {

ConfigurationSpec configurationFromTable(lua_State* L, int table, const std::string& name, const SourceLocation& where,
                                         const SourceLines& lines) {
  const std::string& at = where.file;
  const std::string where_text = where.text();
  ConfigurationSpec spec{name, where, {}};
  const int from = std::max(where.line, 1);
  for (const std::string& component : sortedKeys(L, table, where_text)) {
    lua_pushstring(L, component.c_str());
    lua_rawget(L, table);  // raw: no metamethod can raise here
    const int values = lua_gettop(L);
    const int component_line = lines.find(from, {component});
    const SourceLocation component_at{at, component_line > 0 ? component_line : where.line};
    if (!lua_istable(L, values))
      throw core::Error(component_at.text() + ": " + component + " must be a table of property values");
    for (const std::string& property : sortedKeys(L, values, component_at.text())) {
      lua_pushstring(L, property.c_str());
      lua_rawget(L, values);
      const int line = lines.find(std::max(component_at.line, 1), {property, "="});
      const SourceLocation value_at{at, line > 0 ? line : component_at.line};
      std::string text;
      if (!luaValueText(L, lua_gettop(L), text))
        throw core::Error(value_at.text() + ": " + component + "." + property + " must be a number, boolean, string or "
                          "array of numbers, got " + luaL_typename(L, -1));
      lua_pop(L, 1);
      spec.values.push_back({component, property, text, value_at});
    }
    lua_settop(L, values - 1);
  }
  return spec;
}

}  // namespace detail

ConfigurationSpec loadLuaConfigurationFile(const std::filesystem::path& file) {
  script::LuaState lua(script::LuaMemory{0, "configuration file " + file.string(), ""});
  lua_State* L = lua.get();
  if (const int status = luaL_loadfile(L, file.c_str()); status != LUA_OK) throw core::Error(lua.popError(status));
  if (const int status = lua_pcall(L, 0, 1, 0); status != LUA_OK) throw core::Error(lua.popError(status));
  const std::string at = file.string();
  if (!lua_istable(L, 1)) throw core::Error(at + ": a configuration file must return a table { Component = { property = value } }");
  const detail::SourceLines lines(file.string());
  return detail::configurationFromTable(L, 1, file.stem().string(), {at, 1}, lines);
}

std::vector<ConfigurationSpec> loadLuaConfigurationFolder(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error))
    if (entry.is_regular_file() && entry.path().extension() == ".lua") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<ConfigurationSpec> out;
  for (const auto& file : files) out.push_back(loadLuaConfigurationFile(file));
  return out;
}

}  // namespace cobra::deploy
