#include "cobra/script/lua_component.hpp"

#include <any>

#include "bindings_internal.hpp"
#include "cobra/script/bindings.hpp"
#include "cobra/script/convert.hpp"
#include "lua_guard.hpp"

namespace cobra::script {

namespace {

constexpr const char* kHookNames[] = {"configureHook", "startHook", "updateHook",
                                      "stopHook",      "cleanupHook", "exceptionHook"};
constexpr int kNotAFunction = -100;  // a hook global that is neither nil nor a function

/// Protected: stores a registry reference to each hook function (LUA_NOREF when undefined).
int collectHooks(lua_State* L) {
  auto* refs = static_cast<int*>(lua_touserdata(L, 1));
  for (std::size_t i = 0; i < std::size(kHookNames); ++i) {
    const int type = lua_getglobal(L, kHookNames[i]);
    if (type == LUA_TFUNCTION) {
      refs[i] = luaL_ref(L, LUA_REGISTRYINDEX);
    } else {
      refs[i] = type == LUA_TNIL ? LUA_NOREF : kNotAFunction;
      lua_pop(L, 1);
    }
  }
  return 0;
}

std::string stringArgument(lua_State* L, int index, const char* what, bool optional) {
  if (optional && lua_isnoneornil(L, index)) return {};
  if (lua_type(L, index) != LUA_TSTRING)
    throw core::Error(std::string("argument ") + std::to_string(index - 1) + " (" + what + ") must be a string, got " +
                      describeLuaValue(L, index));
  return lua_tostring(L, index);
}

}  // namespace

/// The declaration methods of `self` in the script (friend: they add owned ports/properties).
struct LuaComponentDeclarations {
  static LuaComponent& self(lua_State* L) {
    auto* c = dynamic_cast<LuaComponent*>(&detail::componentAt(L, 1));
    if (c == nullptr) throw core::Error("only a LuaComponent can declare ports and properties from Lua");
    return *c;
  }

  static const Conversion& conversionFor(LuaComponent& c, const std::string& what, const std::string& name,
                                         const std::string& type) {
    const Conversion* conversion = findConversion(type);
    if (conversion == nullptr)
      throw core::Error("component '" + c.name() + "': cannot declare " + what + " '" + name + "' of type '" + type +
                        "'; Lua can declare the types: " + conversionNames());
    return *conversion;
  }

  static int addPort(lua_State* L, core::PortDirection direction, bool event) {
    LuaComponent& c = self(L);
    const std::string name = stringArgument(L, 2, "name", false);
    const std::string type = stringArgument(L, 3, "type", false);
    const std::string doc = stringArgument(L, 4, "doc", true);
    const std::string unit = stringArgument(L, 5, "unit", true);
    const Conversion& conversion = conversionFor(c, "port", name, type);
    if (core::PortBase* existing = c.findPort(name)) {
      bool own = false;
      for (const auto& p : c.own_ports_) own = own || p.get() == existing;
      if (own && existing->type().name == type && existing->direction() == direction && existing->isEventPort() == event)
        return 0;  // the same declaration, made again by a reloaded script: keep its connections
      throw core::Error("component '" + c.name() + "' already has a port '" + name + "' (" +
                        std::string(existing->type().name) +
                        (existing->direction() == core::PortDirection::Input ? " input" : " output") +
                        "); the script declares it again differently");
    }
    auto port = conversion.make_port(direction, name, doc, unit);
    if (event) c.addEventPort(*port);
    else c.addPort(*port);
    c.own_ports_.push_back(std::move(port));
    return 0;
  }

  static int addInputPort(lua_State* L) { return addPort(L, core::PortDirection::Input, false); }
  static int addEventPort(lua_State* L) { return addPort(L, core::PortDirection::Input, true); }
  static int addOutputPort(lua_State* L) { return addPort(L, core::PortDirection::Output, false); }

  /// Argument 6, {min =, max =}, restricts a double or int property.
  static void applyRange(lua_State* L, LuaComponent& c, core::PropertyBase& property) {
    const std::string where = "component '" + c.name() + "': property '" + property.name() + "'";
    if (lua_type(L, 7) != LUA_TTABLE)
      throw core::Error(where + ": its range (argument 6) must be a table {min =, max =}, got " +
                        describeLuaValue(L, 7));
    double bounds[2];
    const char* names[2] = {"min", "max"};
    for (int i = 0; i < 2; ++i) {
      detail::rawField(L, 7, names[i]);
      if (lua_type(L, -1) != LUA_TNUMBER)
        throw core::Error(where + ": its range (argument 6) needs a number '" + names[i] + "', got " +
                          describeLuaValue(L, -1));
      bounds[i] = static_cast<double>(lua_tonumber(L, -1));
      lua_pop(L, 1);
    }
    if (auto* d = dynamic_cast<core::Property<double>*>(&property)) {
      d->range(bounds[0], bounds[1]);
    } else if (auto* n = dynamic_cast<core::Property<int>*>(&property)) {
      if (bounds[0] != static_cast<int>(bounds[0]) || bounds[1] != static_cast<int>(bounds[1]))
        throw core::Error(where + " is an int: its range (argument 6) needs integer bounds");
      n->range(static_cast<int>(bounds[0]), static_cast<int>(bounds[1]));
    } else {
      throw core::Error(where + " is a " + std::string(property.type().name) +
                        ": only double and int properties take a range");
    }
  }

  static int addProperty(lua_State* L) {
    LuaComponent& c = self(L);
    const std::string name = stringArgument(L, 2, "name", false);
    const std::string type = stringArgument(L, 3, "type", false);
    const std::string unit = stringArgument(L, 5, "unit", true);
    const std::string doc = stringArgument(L, 6, "doc", true);
    const Conversion& conversion = conversionFor(c, "property", name, type);
    std::any initial;
    try {
      conversion.read(L, 4, initial);
    } catch (const core::Error& e) {
      throw core::Error("component '" + c.name() + "': property '" + name + "' is a " + type +
                        ": its initial value (argument 3) is wrong: " + e.what());
    }
    if (core::PropertyBase* existing = c.findProperty(name)) {
      bool own = false;
      for (const auto& p : c.own_properties_) own = own || p.get() == existing;
      if (own && existing->type().name == type) return 0;  // keep the value set from outside
      throw core::Error("component '" + c.name() + "' already has a property '" + name + "' (" +
                        std::string(existing->type().name) + "); the script declares it again differently");
    }
    auto property = conversion.make_property(name, initial, unit, doc);
    if (!lua_isnoneornil(L, 7)) applyRange(L, c, *property);
    c.addProperty(*property);
    c.own_properties_.push_back(std::move(property));
    return 0;
  }
};

LuaComponent::LuaComponent(std::string name, core::Role role, std::string doc)
    : Component(std::move(name), role, std::move(doc)) {
  addProperty(script_path_);
  addProperty(pool_size_.range(0, 1 << 30));
  addProperty(budget_.range(0.0, 3600.0));
  addProperty(load_budget_.range(0.0, 3600.0));
  hooks_.fill(LUA_NOREF);
}

LuaComponent::~LuaComponent() {
  // Stop stepping before members go: the base destructor would do it only after they are gone.
  if (isRunning()) (void)stop();
  lua_.reset();
}

void LuaComponent::loadScript() {
  if (lua_) return;
  const std::string path = script_path_.value();
  if (path.empty())
    throw core::Error("component '" + name() + "': script_path is empty; set it to the Lua file that defines the hooks");
  static const luaL_Reg declarations[] = {{"addInputPort", &detail::guarded<LuaComponentDeclarations::addInputPort>},
                                          {"addEventPort", &detail::guarded<LuaComponentDeclarations::addEventPort>},
                                          {"addOutputPort", &detail::guarded<LuaComponentDeclarations::addOutputPort>},
                                          {"addProperty", &detail::guarded<LuaComponentDeclarations::addProperty>},
                                          {nullptr, nullptr}};
  auto lua = std::make_unique<LuaState>(LuaMemory{static_cast<std::size_t>(pool_size_.value()),
                                                  "component '" + name() + "'", "raise its lua_pool_size property"});
  std::array<int, kHookCount> hooks{};
  lua->setBudget(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(load_budget_.value())),
                 "raise its lua_load_budget property");
  lua->startStep();
  try {
    detail::exposeWith(*lua, *this, "self", declarations);
    exposeComponent(*lua, *this);
    lua->runFile(path);
    detail::protectedCall(lua->get(), &collectHooks, hooks.data(), 0);
  } catch (const core::Error& e) {
    throw core::Error("Lua script of component '" + name() + "' failed: " + e.what());
  }
  for (std::size_t i = 0; i < hooks.size(); ++i)
    if (hooks[i] == kNotAFunction)
      throw core::Error("Lua script of component '" + name() + "' (" + path + "): the global '" + kHookNames[i] +
                        "' must be a function (or nil)");
  hooks_ = hooks;
  lua_ = std::move(lua);
}

void LuaComponent::useBudget(bool load) {
  if (!lua_) return;
  const double limit = load ? load_budget_.value() : budget_.value();
  lua_->setBudget(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(limit)),
                  load ? "raise its lua_load_budget property" : "raise its lua_budget property if the hook needs that long");
}

bool LuaComponent::callHook(Hook hook) {
  if (!lua_ || hooks_[hook] == LUA_NOREF) return true;
  lua_State* L = lua_->get();
  lua_->startStep();
  lua_rawgeti(L, LUA_REGISTRYINDEX, hooks_[hook]);
  lua_->call(0, 1);
  const bool refused = lua_type(L, -1) == LUA_TBOOLEAN && !lua_toboolean(L, -1);
  lua_pop(L, 1);
  return !refused;
}

bool LuaComponent::configureHook() {
  loadScript();
  useBudget(true);
  const bool configured = callHook(kConfigure);
  useBudget(false);  // from here on, steps: start, update, stop, exception
  return configured;
}

bool LuaComponent::startHook() { return callHook(kStart); }
void LuaComponent::updateHook() { callHook(kUpdate); }
void LuaComponent::stopHook() { callHook(kStop); }
void LuaComponent::exceptionHook() { callHook(kException); }

void LuaComponent::cleanupHook() {
  useBudget(true);
  try {
    callHook(kCleanup);
  } catch (...) {
    lua_.reset();
    hooks_.fill(LUA_NOREF);
    throw;
  }
  lua_.reset();
  hooks_.fill(LUA_NOREF);
}

}  // namespace cobra::script
