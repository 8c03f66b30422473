#include "action_check.hpp"

#include <lua.hpp>

#include <algorithm>
#include <any>
#include <stdexcept>
#include <string>

#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/deploy/lua_configuration.hpp"
#include "cobra/deploy/suggest.hpp"
#include "cobra/script/convert.hpp"
#include "cobra/statechart/description.hpp"

namespace cobra::run {
namespace {

// A state trigger fires when its chart enters a state whose full path starts with the trigger's
// (session.cpp): a path no state of the chart starts with never fires.
void checkState(const ActionSpec& a, const Chart& chart, const std::string& at) {
  const statechart::Chart* loaded = chart.supervisor != nullptr ? chart.supervisor->chart() : nullptr;
  if (loaded == nullptr) return;  // a chart of another host: checked there
  std::vector<std::string> paths;
  for (const statechart::ChartDescription::Node& node : statechart::describe(*loaded).nodes)
    if (!node.connector) paths.push_back(node.path);
  const bool found = std::any_of(paths.begin(), paths.end(), [&](const std::string& path) {
    return path.starts_with(a.on.state) && (path.size() == a.on.state.size() || path[a.on.state.size()] == '.');
  });
  if (!found)
    throw std::runtime_error(at + "chart '" + a.on.chart + "' has no state '" + a.on.state + "' (state = \"" +
                             a.on.chart + ":" + a.on.state + "\": the fault would never fire)" +
                             deploy::suggestionText(a.on.state, paths, "states"));
}

// Pushes the value the entry plays (its table's `section`.value: f.set.value, f.write.value);
// false, with nothing pushed, when there is none.
bool pushPlayedValue(lua_State* L, int lua_ref, const char* section) {
  if (lua_ref < 0) return false;
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, lua_ref);  // the entry's table
  if (lua_type(L, -1) == LUA_TTABLE && lua_getfield(L, -1, section) == LUA_TTABLE &&
      lua_getfield(L, -1, "value") != LUA_TNIL) {
    lua_replace(L, top + 1);
    lua_settop(L, top + 1);
    return true;
  }
  lua_settop(L, top);
  return false;
}

// The value a `set` gives its property, checked as a configuration's is (type, range, read-only).
void checkSetValue(const ActionSpec& a, const core::PropertyBase& property, lua_State* L, const std::string& at) {
  const int top = lua_gettop(L);
  if (!pushPlayedValue(L, a.lua_ref, "set")) {
    lua_settop(L, top);
    return;
  }
  std::string text;
  const bool has_text = deploy::luaValueText(L, -1, text);
  const std::string type = luaL_typename(L, -1);
  lua_settop(L, top);
  if (!has_text)
    throw std::runtime_error(at + a.text + ": the value must be a number, boolean, string or array of numbers, got " + type);
  try {
    property.checkText(text);
  } catch (const std::exception& e) {
    throw std::runtime_error(at + a.text + ": " + e.what());
  }
}

// The value a `write` sends on its port, read as the port's type's Lua form.
void checkWriteValue(const ActionSpec& a, const core::PortBase& port, lua_State* L, const std::string& at) {
  const script::Conversion* conversion = script::findConversion(port.type());
  if (conversion == nullptr)
    throw std::runtime_error(at + a.text + ": port '" + port.name() + "' carries " + std::string(port.type().name) +
                             ", which has no Lua form; ports with one carry " + script::conversionNames());
  const int top = lua_gettop(L);
  if (!pushPlayedValue(L, a.lua_ref, "write")) {
    lua_settop(L, top);
    return;
  }
  std::any value;
  try {
    conversion->read(L, lua_gettop(L), value);
  } catch (const std::exception& e) {
    lua_settop(L, top);
    throw std::runtime_error(at + a.text + ": port '" + port.name() + "' carries " + std::string(port.type().name) +
                             ": " + e.what());
  }
  lua_settop(L, top);
}

}  // namespace

void checkAction(const ActionSpec& a, const core::ComponentRegistry& refs, const std::vector<Chart>& charts,
                 lua_State* L) {
  const std::string at = a.where.text() + ": ";
  if (a.on.kind == Trigger::Kind::State) {
    const auto chart = std::find_if(charts.begin(), charts.end(), [&](const Chart& c) { return c.spec->name == a.on.chart; });
    if (chart == charts.end()) {
      std::vector<std::string> names;
      for (const Chart& c : charts) names.push_back(c.spec->name);
      throw std::runtime_error(at + "unknown chart '" + a.on.chart + "' in state '" + a.on.chart + ":" + a.on.state +
                               "'" + deploy::suggestionText(a.on.chart, names, "charts (run.charts)"));
    }
    checkState(a, *chart, at);
  }
  if (a.kind == ActionSpec::Kind::Lua) return;
  core::Component* c = refs.find(a.component);
  if (c == nullptr) {
    std::vector<std::string> names;
    for (const core::Component* each : refs.components()) names.push_back(each->name());
    throw std::runtime_error(at + "unknown component '" + a.component + "' in " + a.text +
                             deploy::suggestionText(a.component, names, "components"));
  }
  if (a.kind == ActionSpec::Kind::Throw) return;  // any component has an updateHook
  std::vector<std::string> known;
  std::string one = "operation", many = "operations";
  if (a.kind == ActionSpec::Kind::Call) {
    if (c->findOperation(a.member) != nullptr) return;
    for (const core::OperationBase* op : c->operations()) known.push_back(op->name());
  } else if (a.kind == ActionSpec::Kind::Write) {
    if (const core::PortBase* port = c->findPort(a.member); port != nullptr) return checkWriteValue(a, *port, L, at);
    one = "port", many = "ports";
    for (const core::PortBase* p : c->ports()) known.push_back(p->name());
  } else {
    if (const core::PropertyBase* property = c->findProperty(a.member); property != nullptr)
      return checkSetValue(a, *property, L, at);
    one = "property", many = "properties";
    for (const core::PropertyBase* p : c->properties()) known.push_back(p->name());
  }
  throw std::runtime_error(at + "component '" + a.component + "' has no " + one + " '" + a.member + "' (" + a.text +
                           ")" + deploy::suggestionText(a.member, known, many));
}

}  // namespace cobra::run
