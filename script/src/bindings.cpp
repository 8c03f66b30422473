#include "cobra/script/bindings.hpp"

#include <any>
#include <vector>

#include "bindings_internal.hpp"
#include "cobra/script/convert.hpp"
#include "lua_guard.hpp"
#include "cobra/script/port_access.hpp"

namespace cobra::script {

namespace {

constexpr const char* kComponentMeta = "cobra.Component";
constexpr const char* kPortMeta = "cobra.Port";
constexpr const char* kObjects = "cobra.objects";  // registry: light userdata Component* -> its object

/// The full userdata behind a port object. `access` is made on first read/write.
struct PortBox {
  core::PortBase* port;
  PortAccess* access;
};

std::string_view keyAt(lua_State* L, int index, const core::Component& c) {
  if (lua_type(L, index) != LUA_TSTRING)
    throw core::Error("component '" + c.name() + "': index it with a name (a string), not " +
                      describeLuaValue(L, index));
  std::size_t n = 0;
  const char* s = lua_tolstring(L, index, &n);
  return {s, n};
}

template <class List>
std::string namesOf(const List& list) {
  std::string names;
  for (const auto& item : list) names += (names.empty() ? "" : ", ") + item->name();
  return names.empty() ? "(none)" : names;
}

std::string noElement(const core::Component& c, std::string_view name) {
  return "component '" + c.name() + "' has no port, property or operation '" + std::string(name) +
         "'; its ports are: " + namesOf(c.ports()) + "; its properties are: " + namesOf(c.properties()) +
         "; its operations are: " + namesOf(c.operations()) +
         "; its methods are: configure, start, stop, cleanup, recover, getState, getName, getRole, getLastError, now, emitEvent";
}

// ---- Port objects -------------------------------------------------------------------------

PortBox& portAt(lua_State* L) {
  auto* box = static_cast<PortBox*>(luaL_testudata(L, 1, kPortMeta));
  if (box == nullptr) throw core::Error("call port methods with ':' (port:read()), not '.'");
  return *box;
}

PortAccess& accessOf(PortBox& box) {
  if (box.access == nullptr) {
    const Conversion* conversion = findConversion(box.port->type());
    box.access = (conversion ? conversion->access(*box.port) : makeTextPortAccess(*box.port)).release();
  }
  return *box.access;
}

int portRead(lua_State* L) { return accessOf(portAt(L)).read(L); }
int portWrite(lua_State* L) {
  PortBox& box = portAt(L);
  if (lua_gettop(L) != 2) throw core::Error("port " + box.port->fullName() + ": write takes one value");
  return accessOf(box).write(L, 2);
}
int portName(lua_State* L) {
  detail::pushString(L, portAt(L).port->name());
  return 1;
}
int portType(lua_State* L) {
  detail::pushString(L, portAt(L).port->type().name);
  return 1;
}
int portUnit(lua_State* L) {
  detail::pushString(L, portAt(L).port->unit());
  return 1;
}
int portDoc(lua_State* L) {
  detail::pushString(L, portAt(L).port->doc());
  return 1;
}
int portConnected(lua_State* L) {
  lua_pushboolean(L, portAt(L).port->connected() ? 1 : 0);
  return 1;
}
int portToString(lua_State* L) {
  const core::PortBase& port = *portAt(L).port;
  detail::pushString(L, "port " + port.fullName() + " (" + std::string(port.type().name) + ", " +
                            (port.direction() == core::PortDirection::Input ? "input" : "output") + ")");
  return 1;
}
int portGc(lua_State* L) {
  auto* box = static_cast<PortBox*>(lua_touserdata(L, 1));
  delete box->access;
  box->access = nullptr;
  return 0;
}

// ---- Component objects --------------------------------------------------------------------

int operationCall(lua_State* L) {
  core::OperationBase& op = *static_cast<core::OperationBase*>(lua_touserdata(L, lua_upvalueindex(1)));
  const int first = lua_gettop(L) >= 1 && lua_rawequal(L, 1, lua_upvalueindex(2)) ? 2 : 1;
  const auto given = static_cast<std::size_t>(lua_gettop(L) - first + 1);
  const auto& arguments = op.arguments();
  if (given != arguments.size())
    throw core::Error(op.where() + " expects " + std::to_string(arguments.size()) + " argument(s), got " +
                      std::to_string(given));
  auto argumentName = [&](std::size_t i) {
    return "argument " + std::to_string(i + 1) + (arguments[i].name.empty() ? "" : " ('" + arguments[i].name + "')");
  };
  bool typed = op.resultType() == nullptr || findConversion(*op.resultType()) != nullptr;
  for (const auto& a : arguments) typed = typed && findConversion(*a.type) != nullptr;
  if (typed) {
    std::vector<std::any> values(given);
    for (std::size_t i = 0; i < given; ++i) {
      try {
        findConversion(*arguments[i].type)->read(L, first + static_cast<int>(i), values[i]);
      } catch (const core::Error& e) {
        throw core::Error(op.where() + ": " + argumentName(i) + " must be a " + std::string(arguments[i].type->name) +
                          ": " + e.what());
      }
    }
    const std::any result = op.invoke(values);
    if (op.resultType() == nullptr) return 0;
    findConversion(*op.resultType())->push(L, result);
    return 1;
  }
  // Some type has no conversion: go through the text forms.
  std::vector<std::string> texts;
  for (std::size_t i = 0; i < given; ++i) {
    const int index = first + static_cast<int>(i);
    if (lua_type(L, index) == LUA_TSTRING) texts.emplace_back(lua_tostring(L, index));
    else if (lua_type(L, index) == LUA_TNUMBER) texts.push_back(core::printValue(static_cast<double>(lua_tonumber(L, index))));
    else if (lua_type(L, index) == LUA_TBOOLEAN) texts.emplace_back(lua_toboolean(L, index) ? "true" : "false");
    else
      throw core::Error(op.where() + ": " + argumentName(i) + " is a " + std::string(arguments[i].type->name) +
                        ", which Lua passes as text: expected a string (" + std::string(arguments[i].type->format) +
                        "), got " + describeLuaValue(L, index));
  }
  const std::string result = op.invokeFromText(texts);
  if (op.resultType() == nullptr) return 0;
  detail::pushString(L, result);
  return 1;
}

/// Protected: stack (cache, key, light userdata port) -> the new port object, cached.
int newPortObject(lua_State* L) {
  auto* box = static_cast<PortBox*>(lua_newuserdatauv(L, sizeof(PortBox), 0));
  *box = PortBox{static_cast<core::PortBase*>(lua_touserdata(L, 3)), nullptr};
  luaL_setmetatable(L, kPortMeta);
  lua_pushvalue(L, 2);
  lua_pushvalue(L, -2);
  lua_rawset(L, 1);
  return 1;
}

/// Protected: stack (cache, key, light userdata operation, component object) -> the closure.
int newOperationObject(lua_State* L) {
  lua_pushvalue(L, 3);
  lua_pushvalue(L, 4);
  lua_pushcclosure(L, &detail::guarded<operationCall>, 2);
  lua_pushvalue(L, 2);
  lua_pushvalue(L, -2);
  lua_rawset(L, 1);
  return 1;
}

/// Makes (once) and pushes the cached object of an element, with `maker` in protected mode.
void pushCached(lua_State* L, lua_CFunction maker, void* element) {
  lua_pushcfunction(L, maker);
  lua_getiuservalue(L, 1, 1);
  lua_pushvalue(L, 2);
  lua_pushlightuserdata(L, element);
  lua_pushvalue(L, 1);
  const int status = lua_pcall(L, 4, 1, 0);
  if (status != LUA_OK) throw core::Error(LuaState::from(L)->popError(status, L));
}

void pushProperty(lua_State* L, const core::PropertyBase& property) {
  if (const Conversion* conversion = findConversion(property.type()))
    conversion->push(L, conversion->get_property(property));
  else
    detail::pushString(L, property.valueText());
}

int componentIndex(lua_State* L) {
  core::Component& c = detail::componentAt(L, 1);
  const std::string_view name = keyAt(L, 2, c);
  lua_pushvalue(L, 2);
  if (lua_rawget(L, lua_upvalueindex(1)) != LUA_TNIL) return 1;  // a method
  lua_getiuservalue(L, 1, 1);
  lua_pushvalue(L, 2);
  if (lua_rawget(L, -2) != LUA_TNIL) return 1;  // a port or operation object made before
  lua_settop(L, 2);
  if (const core::PropertyBase* property = c.findProperty(name)) {
    pushProperty(L, *property);
    return 1;
  }
  if (core::PortBase* port = c.findPort(name)) {
    pushCached(L, &newPortObject, port);
    return 1;
  }
  if (core::OperationBase* op = c.findOperation(name)) {
    pushCached(L, &newOperationObject, op);
    return 1;
  }
  throw core::Error(noElement(c, name));
}

int componentNewIndex(lua_State* L) {
  core::Component& c = detail::componentAt(L, 1);
  const std::string_view name = keyAt(L, 2, c);
  core::PropertyBase* property = c.findProperty(name);
  if (property == nullptr) {
    if (c.findPort(name) != nullptr || c.findOperation(name) != nullptr)
      throw core::Error("component '" + c.name() + "': '" + std::string(name) + "' is a " +
                        (c.findPort(name) ? "port" : "operation") + "; only properties can be assigned");
    (void)c.property(name);  // throws the core's "has no property ...; its properties are: ..."
  }
  const std::string type(property->type().name);
  if (const Conversion* conversion = findConversion(property->type())) {
    std::any value;
    try {
      conversion->read(L, 3, value);
    } catch (const core::Error& e) {
      throw core::Error(property->where() + " is a " + type + ": cannot set it from Lua: " + e.what());
    }
    conversion->set_property(*property, value);
    return 0;
  }
  if (lua_type(L, 3) != LUA_TSTRING)
    throw core::Error(property->where() + " is a " + type + ", which Lua sets from text: expected a string (" +
                      std::string(property->type().format) + "), got " + describeLuaValue(L, 3));
  property->setFromText(lua_tostring(L, 3));
  return 0;
}

int componentDescribe(lua_State* L) {
  detail::pushString(L, core::toText(core::describe(detail::componentAt(L, 1))));
  return 1;
}

template <core::Result (core::Component::*Call)()>
int lifecycle(lua_State* L) {
  core::Component& c = detail::componentAt(L, 1);
  const core::Result result = (c.*Call)();
  if (!result) throw core::Error(result.message);
  lua_pushboolean(L, 1);
  return 1;
}

int getState(lua_State* L) {
  detail::pushString(L, core::toString(detail::componentAt(L, 1).state()));
  return 1;
}
int getName(lua_State* L) {
  detail::pushString(L, detail::componentAt(L, 1).name());
  return 1;
}
int getRole(lua_State* L) {
  detail::pushString(L, core::toString(detail::componentAt(L, 1).role()));
  return 1;
}
/// Seconds on the component's activity clock (simulated time on the lockstep clock).
int now(lua_State* L) {
  lua_pushnumber(L, std::chrono::duration<double>(detail::componentAt(L, 1).now()).count());
  return 1;
}
/// Writes an event from the component on its `events` port. Real-time safe.
int emitEvent(lua_State* L) {
  core::Component& c = detail::componentAt(L, 1);
  if (lua_type(L, 2) != LUA_TSTRING)
    throw core::Error("component '" + c.name() + "': emitEvent takes an event name (a string), got " +
                      describeLuaValue(L, 2));
  std::size_t n = 0;
  const char* name = lua_tolstring(L, 2, &n);
  c.emitEvent(std::string_view(name, n));
  return 0;
}
int getLastError(lua_State* L) {
  detail::pushString(L, detail::componentAt(L, 1).lastError());
  return 1;
}

/// Protected: creates the metatables once per state.
void makeMetatables(lua_State* L) {
  if (luaL_newmetatable(L, kComponentMeta)) {
    static const luaL_Reg methods[] = {{"configure", &detail::guarded<lifecycle<&core::Component::configure>>},
                                       {"start", &detail::guarded<lifecycle<&core::Component::start>>},
                                       {"stop", &detail::guarded<lifecycle<&core::Component::stop>>},
                                       {"cleanup", &detail::guarded<lifecycle<&core::Component::cleanup>>},
                                       {"recover", &detail::guarded<lifecycle<&core::Component::recover>>},
                                       {"getState", &detail::guarded<getState>},
                                       {"getName", &detail::guarded<getName>},
                                       {"getRole", &detail::guarded<getRole>},
                                       {"getLastError", &detail::guarded<getLastError>},
                                       {"now", &detail::guarded<now>},
                                       {"emitEvent", &detail::guarded<emitEvent>},
                                       {nullptr, nullptr}};
    luaL_newlib(L, methods);
    lua_pushcclosure(L, &detail::guarded<componentIndex>, 1);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, &detail::guarded<componentNewIndex>);
    lua_setfield(L, -2, "__newindex");
    lua_pushcfunction(L, &detail::guarded<componentDescribe>);
    lua_setfield(L, -2, "__call");
    lua_pushcfunction(L, &detail::guarded<componentDescribe>);
    lua_setfield(L, -2, "__tostring");
  }
  lua_pop(L, 1);
  if (luaL_newmetatable(L, kPortMeta)) {
    static const luaL_Reg methods[] = {{"read", &detail::guarded<portRead>},
                                       {"write", &detail::guarded<portWrite>},
                                       {"name", &detail::guarded<portName>},
                                       {"type", &detail::guarded<portType>},
                                       {"unit", &detail::guarded<portUnit>},
                                       {"doc", &detail::guarded<portDoc>},
                                       {"connected", &detail::guarded<portConnected>},
                                       {nullptr, nullptr}};
    luaL_newlib(L, methods);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, &detail::guarded<portToString>);
    lua_setfield(L, -2, "__tostring");
    lua_pushcfunction(L, &portGc);
    lua_setfield(L, -2, "__gc");
  }
  lua_pop(L, 1);
}

struct ExposeJob {
  core::Component* component;
  const char* global;
  const luaL_Reg* extras;
};

/// Protected: finds or makes the component's object and sets the global.
int exposeThunk(lua_State* L) {
  const auto& job = *static_cast<const ExposeJob*>(lua_touserdata(L, 1));
  makeMetatables(L);
  if (lua_getfield(L, LUA_REGISTRYINDEX, kObjects) != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setfield(L, LUA_REGISTRYINDEX, kObjects);
  }
  lua_pushlightuserdata(L, job.component);
  if (lua_rawget(L, -2) != LUA_TUSERDATA) {
    lua_pop(L, 1);
    *static_cast<core::Component**>(lua_newuserdatauv(L, sizeof(core::Component*), 1)) = job.component;
    luaL_setmetatable(L, kComponentMeta);
    lua_newtable(L);
    lua_setiuservalue(L, -2, 1);
    lua_pushlightuserdata(L, job.component);
    lua_pushvalue(L, -2);
    lua_rawset(L, -4);
  }
  if (job.extras != nullptr) {
    lua_getiuservalue(L, -1, 1);
    luaL_setfuncs(L, job.extras, 0);
    lua_pop(L, 1);
  }
  lua_setglobal(L, job.global);
  return 0;
}

int refreshReferences(lua_State* L) {
  auto& registry = *static_cast<core::ComponentRegistry*>(lua_touserdata(L, lua_upvalueindex(1)));
  LuaState* lua = LuaState::from(L);
  for (core::Component* c : registry.components()) exposeComponent(*lua, *c);
  return 0;
}

int installGetReferences(lua_State* L) {
  lua_pushvalue(L, 1);  // the registry, as light userdata
  lua_pushcclosure(L, &detail::guarded<refreshReferences>, 1);
  lua_setglobal(L, "getReferences");
  return 0;
}

}  // namespace

core::Component& detail::componentAt(lua_State* L, int index) {
  auto* slot = static_cast<core::Component**>(luaL_testudata(L, index, kComponentMeta));
  if (slot == nullptr) throw core::Error("call component methods with ':' (Comp:start()), not '.' (Comp.start())");
  return **slot;
}

void detail::exposeWith(LuaState& lua, core::Component& component, const std::string& global, const luaL_Reg* extras) {
  const ExposeJob job{&component, global.c_str(), extras};
  detail::protectedCall(lua.get(), &exposeThunk, &job, 0);
}

void exposeComponent(LuaState& lua, core::Component& component, const std::string& global) {
  detail::exposeWith(lua, component, global, nullptr);
}

void exposeComponent(LuaState& lua, core::Component& component) { exposeComponent(lua, component, component.name()); }

void getReferences(LuaState& lua, core::ComponentRegistry& registry) {
  for (core::Component* c : registry.components()) exposeComponent(lua, *c);
  detail::protectedCall(lua.get(), &installGetReferences, &registry, 0);
}

}  // namespace cobra::script
