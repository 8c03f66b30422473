#include "lua_placement.hpp"

#include <algorithm>

#include "cobra/core/error.hpp"
#include "source_lines.hpp"

namespace cobra::deploy::detail {
namespace {

[[noreturn]] void fail(const SourceLocation& where, const std::string& what) {
  throw core::Error(where.text() + ": placement: " + what);
}

/// The list of names at the top of the stack (popped by the caller).
std::vector<std::string> names(lua_State* L, const SourceLocation& where, const std::string& what) {
  if (!lua_istable(L, -1)) fail(where, what + " must be a list of component names or patterns (\"Needle*\")");
  std::vector<std::string> out;
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    if (lua_type(L, -1) != LUA_TSTRING) fail(where, what + " entry " + std::to_string(i) + " must be a string");
    out.emplace_back(lua_tostring(L, -1));
    lua_pop(L, 1);
  }
  return out;
}

}  // namespace

PlacementSpec readPlacement(lua_State* L, int index, const std::string& entry_file) {
  index = lua_absindex(L, index);
  const SourceLines lines(entry_file);
  PlacementSpec spec;
  int line = lines.find(1, {"placement = {"});
  if (line == 0) line = lines.find(1, {"placement"});
  spec.where = {entry_file, line};
  if (!lua_istable(L, index)) fail(spec.where, std::string("must be a table, got ") + luaL_typename(L, index));
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {  // key at -2, value at -1
    const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "?";
    if (key == "hosts") {
      if (!lua_istable(L, -1)) fail(spec.where, "hosts must be a table { host = { \"Component\", ... } }");
      lua_pushnil(L);
      while (lua_next(L, -2) != 0) {
        if (lua_type(L, -2) != LUA_TSTRING) fail(spec.where, "hosts' keys must be host names, e.g. needle = { ... }");
        PlacementSpec::Host host;
        host.name = lua_tostring(L, -2);
        int at = lines.find(std::max(line, 1), {host.name + " = {"});
        if (at == 0) at = line;
        host.where = {entry_file, at};
        host.patterns = names(L, host.where, "host '" + host.name + "'");
        spec.hosts.push_back(std::move(host));
        lua_pop(L, 1);
      }
    } else if (key == "everywhere") {
      spec.everywhere = names(L, spec.where, "everywhere");
    } else if (key == "transport") {
      if (lua_type(L, -1) != LUA_TSTRING) fail(spec.where, "transport must be a transport's name, e.g. \"dds\"");
      spec.transport = lua_tostring(L, -1);
    } else if (key == "qos") {
      if (!lua_istable(L, -1)) fail(spec.where, "qos must be a table, e.g. { reliability = \"reliable\" }");
      lua_pushnil(L);
      while (lua_next(L, -2) != 0) {
        const int type = lua_type(L, -1);
        if (lua_type(L, -2) != LUA_TSTRING || (type != LUA_TSTRING && type != LUA_TNUMBER))
          fail(spec.where, "qos entries must be name = string or number");
        lua_pushvalue(L, -1);  // lua_tostring converts in place: convert a copy
        spec.qos.emplace_back(lua_tostring(L, -3), lua_tostring(L, -1));
        lua_pop(L, 2);
      }
    } else {
      fail(spec.where, "unknown key '" + key + "'; placement has hosts, everywhere, transport and qos");
    }
    lua_pop(L, 1);
  }
  // Lua's table order is not the file's: sorted, so that errors and topics are stable.
  std::sort(spec.hosts.begin(), spec.hosts.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::sort(spec.qos.begin(), spec.qos.end());
  return spec;
}

}  // namespace cobra::deploy::detail
