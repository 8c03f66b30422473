#include "motion_types.hpp"

#include <string>

#include <lua.hpp>

namespace cobra::script {

namespace {
constexpr std::string_view kPathForm = "an array of waypoints, each an array of axis values {{0, 0.1}, {0.2, 0.3}}";
}

std::string_view LuaCodec<trajectory::MultiAxisPath>::form() { return kPathForm; }

void LuaCodec<trajectory::MultiAxisPath>::read(lua_State* L, int index, trajectory::MultiAxisPath& out) {
  index = lua_absindex(L, index);
  if (lua_type(L, index) != LUA_TTABLE) lua_codec::refuse(L, index, kPathForm);
  lua_codec::StackGuard guard(L);
  const auto count = static_cast<std::size_t>(lua_rawlen(L, index));
  std::vector<std::vector<double>> waypoints(count);
  for (std::size_t k = 0; k < count; ++k) {
    if (lua_rawgeti(L, index, static_cast<lua_Integer>(k + 1)) != LUA_TTABLE)
      lua_codec::refuse(L, index, kPathForm, "waypoint " + std::to_string(k + 1) + " is not an array");
    const int waypoint = lua_gettop(L);
    const auto axes = static_cast<std::size_t>(lua_rawlen(L, waypoint));
    waypoints[k].resize(axes);
    for (std::size_t a = 0; a < axes; ++a) {
      if (lua_rawgeti(L, waypoint, static_cast<lua_Integer>(a + 1)) != LUA_TNUMBER)
        lua_codec::refuse(L, index, kPathForm,
                          "waypoint " + std::to_string(k + 1) + ", value " + std::to_string(a + 1) + " is not a number");
      waypoints[k][a] = static_cast<double>(lua_tonumber(L, -1));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  out = trajectory::MultiAxisPath(std::move(waypoints));
}

void LuaCodec<trajectory::MultiAxisPath>::push(lua_State* L, const trajectory::MultiAxisPath& value) {
  lua_createtable(L, static_cast<int>(value.size()), 0);
  for (std::size_t k = 0; k < value.size(); ++k) {
    const std::vector<double>& waypoint = value.waypoint(k);
    lua_createtable(L, static_cast<int>(waypoint.size()), 0);
    for (std::size_t a = 0; a < waypoint.size(); ++a) {
      lua_pushnumber(L, waypoint[a]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(a + 1));
    }
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
}

}  // namespace cobra::script
