#pragma once
// What LuaComponent adds to the bindings (internal to cobra::script).

#include <lua.hpp>

#include <string>

#include "cobra/core/component.hpp"
#include "cobra/script/lua_state.hpp"

namespace cobra::script::detail {

/// exposeComponent, with `extras` (a luaL_Reg list ending in {nullptr, nullptr}) added as
/// methods of this one component's object.
void exposeWith(LuaState& lua, core::Component& component, const std::string& global, const luaL_Reg* extras);

/// The component of the object at `index`. @throws core::Error when it is not a component
/// object (usually '.' written instead of ':').
core::Component& componentAt(lua_State* L, int index);

}  // namespace cobra::script::detail
