// rFSM models in Lua -> cobra's statechart engine (see rfsm.hpp). The Lua side (model
// constructors, the walk that flattens a model into a description) is rfsm_prelude.lua; this
// file builds the chart from the description and calls back into Lua. Lua errors never longjmp
// over C++ frames: calls are protected and C functions go through detail::guarded (lua_guard.hpp).

#include "cobra/script/rfsm.hpp"

#include <lua.hpp>

#include <cstdio>
#include <stdexcept>

#include "lua_guard.hpp"
#include "rfsm_prelude.hpp"

namespace cobra::script {
namespace {

using statechart::DooStatus;
using statechart::Machine;
using statechart::StepResult;

// Registry keys (their addresses): the module's C table, machines bound to models, and the
// machines owned by models that rfsm.init made.
const char kModuleKey = 0;
const char kBoundKey = 0;
const char kOwnedKey = 0;

// Description layout (rfsm_prelude.lua, C.describe).
enum DescriptionField { kNodes = 1, kTransitions = 2, kRoot = 3, kWords = 4, kEvents = 5, kThreads = 6, kRootCallbacks = 7 };
enum NodeSlot { kNodeKind = 1, kNodeParent, kNodeName, kNodeOrigin, kNodeEntry, kNodeExit, kNodeDoo, kNodeTable };
enum TransitionSlot { kScope = 1, kSrc, kTgt, kEventList, kPn, kGuard, kEffect, kTransitionOrigin, kTransitionTable };
enum Word { kEntryWord = 1, kExitWord, kDooWord, kEffectWord };

std::string popMessage(lua_State* L) {
  std::string message = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "Lua error (not a string)";
  lua_pop(L, 1);
  return message;
}

/// The string at `index` (which must be a string; never converts, so never raises).
std::string stringAt(lua_State* L, int index) {
  std::size_t length = 0;
  const char* text = lua_type(L, index) == LUA_TSTRING ? lua_tolstring(L, index, &length) : "";
  return std::string(text, length);
}

/// Pushes registry[key][object at `index`] (nil when absent). Raises nothing.
void pushMapped(lua_State* L, const char* key, int index) {
  index = lua_absindex(L, index);
  if (lua_rawgetp(L, LUA_REGISTRYINDEX, key) != LUA_TTABLE) return;
  lua_pushvalue(L, index);
  lua_rawget(L, -2);
  lua_remove(L, -2);
}

/// registry[key][object at `index`] = value on top (popped); the map is made weak-keyed on first
/// use. Protected: growing the map may allocate.
void setMapped(lua_State* L, const char* key, int index) {
  index = lua_absindex(L, index);
  lua_pushcfunction(L, [](lua_State* S) -> int {  // (key, object, value)
    const void* map_key = lua_touserdata(S, 1);
    if (lua_rawgetp(S, LUA_REGISTRYINDEX, map_key) != LUA_TTABLE) {
      lua_pop(S, 1);
      lua_newtable(S);
      lua_newtable(S);
      lua_pushliteral(S, "k");
      lua_setfield(S, -2, "__mode");
      lua_setmetatable(S, -2);
      lua_pushvalue(S, -1);
      lua_rawsetp(S, LUA_REGISTRYINDEX, map_key);
    }
    lua_pushvalue(S, 2);
    lua_pushvalue(S, 3);
    lua_rawset(S, -3);
    return 0;
  });
  lua_pushlightuserdata(L, const_cast<char*>(key));
  lua_pushvalue(L, index);
  lua_pushvalue(L, -4);  // the value
  const int status = lua_pcall(L, 3, 0, 0);
  if (status != LUA_OK) {
    LuaState* owner = LuaState::from(L);
    std::string message = owner != nullptr ? owner->popError(status, L) : popMessage(L);
    lua_pop(L, 1);
    throw core::Error(message);
  }
  lua_pop(L, 1);  // the value
}

Machine* boundMachine(lua_State* L, int model) {
  pushMapped(L, &kBoundKey, model);
  auto* machine = lua_type(L, -1) == LUA_TLIGHTUSERDATA ? static_cast<Machine*>(lua_touserdata(L, -1)) : nullptr;
  lua_pop(L, 1);
  return machine;
}

}  // namespace

/// What rfsm.init makes: the chart and its machine, owned by a Lua userdata (freed by __gc).
struct RfsmAccess {
  struct Owned {
    std::unique_ptr<RfsmChart> chart;
    std::unique_ptr<Machine> machine;
  };
  static Owned* owned(lua_State* L, int model) {
    pushMapped(L, &kOwnedKey, model);
    auto* o = lua_type(L, -1) == LUA_TUSERDATA ? static_cast<Owned*>(lua_touserdata(L, -1)) : nullptr;
    lua_pop(L, 1);
    return o;
  }
  static Machine& machine(lua_State* L, int model) {
    if (Machine* bound = boundMachine(L, model)) return *bound;
    if (Owned* o = owned(L, model)) return *o->machine;
    throw core::Error("this fsm was not initialised: call rfsm.init(model) first");
  }
  static std::unique_ptr<RfsmChart> describeModel(LuaState& lua, int model) {
    lua_State* L = lua.get();
    model = lua_absindex(L, model);
    lua_rawgetp(L, LUA_REGISTRYINDEX, &kModuleKey);
    lua_getfield(L, -1, "describe");  // a field of our own table: no metamethod, no allocation
    lua_remove(L, -2);
    lua_pushvalue(L, model);
    const int status = lua_pcall(L, 1, 1, 0);
    if (status != LUA_OK) throw core::Error(lua.popError(status));
    const int ref = luaL_ref(L, LUA_REGISTRYINDEX);
    std::unique_ptr<RfsmChart> chart(new RfsmChart(lua, ref));
    chart->build();
    return chart;
  }

  static int init(lua_State* L) {
    LuaState* lua = LuaState::from(L);
    if (lua == nullptr || !lua_istable(L, 1)) throw core::Error("rfsm.init: expected a model");
    auto chart = describeModel(*lua, 1);
    // The userdata (with its __gc) is made in protected mode: it allocates.
    detail::protectedCall(
        L,
        [](lua_State* S) -> int {
          lua_newuserdatauv(S, sizeof(Owned), 0);
          lua_createtable(S, 0, 1);
          lua_pushcfunction(S, [](lua_State* T) -> int {
            auto* owned = static_cast<Owned*>(lua_touserdata(T, 1));
            if (owned->chart) owned->chart->lua_ = nullptr;  // finalising: no more Lua calls from C++
            owned->~Owned();
            return 0;
          });
          lua_setfield(S, -2, "__gc");
          lua_setmetatable(S, -2);
          return 1;
        },
        nullptr, 1);
    auto* o = new (lua_touserdata(L, -1)) Owned{std::move(chart), nullptr};
    o->machine = std::make_unique<Machine>(o->chart->chart(), [L] { return gettime(L); });
    o->chart->bind(o->machine.get());
    setMapped(L, &kOwnedKey, 1);
    return 0;
  }
  /// rfsm_timeevent's hook (ns, as rFSM's), else the steady clock.
  static std::chrono::nanoseconds gettime(lua_State* L) {
    lua_rawgetp(L, LUA_REGISTRYINDEX, &kModuleKey);
    const int type = lua_getfield(L, -1, "gettime");
    lua_remove(L, -2);
    if (type != LUA_TFUNCTION) {
      lua_pop(L, 1);
      return std::chrono::steady_clock::now().time_since_epoch();
    }
    // The machine reads its clock in a step, which must not throw: a failing hook is reported
    // and the steady clock stands in for it.
    if (lua_pcall(L, 0, 1, 0) != LUA_OK) {
      std::fprintf(stderr, "[cobra] rfsm_timeevent gettime hook failed (the steady clock is used): %s\n",
                   popMessage(L).c_str());
      return std::chrono::steady_clock::now().time_since_epoch();
    }
    const auto ns = static_cast<std::int64_t>(lua_tonumber(L, -1));
    lua_pop(L, 1);
    return std::chrono::nanoseconds(ns);
  }
  static int send(lua_State* L) {
    Machine& m = machine(L, 1);
    if (lua_type(L, 2) != LUA_TSTRING) throw core::Error("rfsm.send_events: events are strings");
    std::size_t length = 0;
    const char* text = lua_tolstring(L, 2, &length);
    if (m.raise(std::string_view(text, length)) != statechart::RaiseStatus::Queued)
      throw core::Error("rfsm.send_events: event '" + std::string(text, length) + "' not queued (queue full or name too long)");
    return 0;
  }
  static int step(lua_State* L) {
    const char* names[] = {"entered", "transitioned", "events_ignored", "doo_ran", "idle", "cannot_enter"};
    const StepResult r = machine(L, 1).step();
    detail::pushString(L, names[static_cast<int>(r)]);
    return 1;
  }
  static int leaf(lua_State* L) {
    const std::string_view fqn = machine(L, 1).activeLeaf();
    if (fqn.empty()) lua_pushnil(L);
    else detail::pushString(L, fqn);
    return 1;
  }
  static int configuration(lua_State* L) {
    Machine& m = machine(L, 1);
    lua_createtable(L, 8, 0);
    int i = 0;
    for (const auto& node : m.chart().nodes()) {
      if (node.kind == statechart::NodeKind::State && m.isActive(node.fqn)) {
        detail::pushString(L, node.fqn);
        lua_rawseti(L, -2, ++i);
      }
    }
    return 1;
  }
  static int reset(lua_State* L) {
    machine(L, 1).reset();
    return 0;
  }
};

void installRfsm(LuaState& lua) {
  lua_State* L = lua.get();
  if (lua_rawgetp(L, LUA_REGISTRYINDEX, &kModuleKey) == LUA_TTABLE) {
    lua_pop(L, 1);
    return;
  }
  lua_pop(L, 1);
  detail::protectedCall(
      L,
      [](lua_State* S) -> int {
        const luaL_Reg functions[] = {{"init", detail::guarded<RfsmAccess::init>},
                                      {"send", detail::guarded<RfsmAccess::send>},
                                      {"step", detail::guarded<RfsmAccess::step>},
                                      {"leaf", detail::guarded<RfsmAccess::leaf>},
                                      {"configuration", detail::guarded<RfsmAccess::configuration>},
                                      {"reset", detail::guarded<RfsmAccess::reset>},
                                      {nullptr, nullptr}};
        luaL_newlib(S, functions);
        lua_pushvalue(S, -1);
        lua_rawsetp(S, LUA_REGISTRYINDEX, &kModuleKey);
        return 1;
      },
      nullptr, 1);
  if (luaL_loadbuffer(L, kRfsmPrelude, sizeof(kRfsmPrelude) - 1, "=rfsm") != LUA_OK) throw core::Error(popMessage(L));
  lua_insert(L, -2);  // prelude, C
  const int status = lua_pcall(L, 1, 1, 0);
  if (status != LUA_OK) throw core::Error(lua.popError(status));
  lua_setglobal(L, "rfsm");
}

namespace {

/// Pushes the field `field` of the chart's description (the registry's `description`).
void pushDescriptionField(lua_State* S, int description, int field) {
  lua_rawgeti(S, LUA_REGISTRYINDEX, description);
  lua_rawgeti(S, -1, field);
  lua_remove(S, -2);
}

/// Pushes the interned word `word` ("entry", "effect", ...: rFSM passes it to a callback).
void pushWord(lua_State* S, int description, int word) {
  pushDescriptionField(S, description, kWords);
  lua_rawgeti(S, -1, word);
  lua_remove(S, -2);
}

/// Runs the chunk on top of the stack and builds the chart it returns; `name` for messages.
std::unique_ptr<RfsmChart> runChunk(LuaState& lua, const std::string& name) {
  lua_State* L = lua.get();
  const int status = lua_pcall(L, 0, 1, 0);
  if (status != LUA_OK) throw core::Error(lua.popError(status));
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    throw core::Error(name + ": the chart must return an rfsm.state (return rfsm.state{ ... })");
  }
  try {
    auto chart = RfsmAccess::describeModel(lua, -1);
    lua_pop(L, 1);
    return chart;
  } catch (...) {
    lua_pop(L, 1);
    throw;
  }
}

}  // namespace

std::unique_ptr<RfsmChart> RfsmChart::loadFile(LuaState& lua, const std::string& path) {
  installRfsm(lua);
  if (luaL_loadfile(lua.get(), path.c_str()) != LUA_OK) throw core::Error("cannot load chart " + popMessage(lua.get()));
  return runChunk(lua, path);
}

std::unique_ptr<RfsmChart> RfsmChart::loadString(LuaState& lua, const std::string& code, const std::string& chunk_name) {
  installRfsm(lua);
  if (luaL_loadbuffer(lua.get(), code.data(), code.size(), chunk_name.c_str()) != LUA_OK)
    throw core::Error(popMessage(lua.get()));
  return runChunk(lua, chunk_name.starts_with("@") || chunk_name.starts_with("=") ? chunk_name.substr(1) : chunk_name);
}

RfsmChart::RfsmChart(LuaState& lua, int description_ref) : lua_(&lua), description_ref_(description_ref) {}

RfsmChart::~RfsmChart() {
  if (lua_ == nullptr) return;  // finalised with its Lua state (rfsm.init's charts)
  bind(nullptr);
  luaL_unref(lua_->get(), LUA_REGISTRYINDEX, description_ref_);
}

void RfsmChart::bind(statechart::Machine* machine) {
  lua_State* L = lua_->get();
  lua_rawgeti(L, LUA_REGISTRYINDEX, description_ref_);
  lua_rawgeti(L, -1, kRoot);
  if (machine == nullptr) lua_pushnil(L);
  else lua_pushlightuserdata(L, machine);
  setMapped(L, &kBoundKey, -2);
  lua_pop(L, 2);
}

void RfsmChart::pushSlot(int list, int index, int slot) const {
  lua_State* L = lua_->get();
  lua_rawgeti(L, LUA_REGISTRYINDEX, description_ref_);
  lua_rawgeti(L, -1, list);
  lua_rawgeti(L, -1, index);
  lua_rawgeti(L, -1, slot);
  lua_replace(L, -4);
  lua_pop(L, 2);
}

void RfsmChart::callLua(int arguments, const char* callback) const {
  lua_State* L = lua_->get();
  const int status = lua_pcall(L, arguments, 1, 0);
  if (status != LUA_OK) {
    LuaState* owner = LuaState::from(L);
    throw std::runtime_error(owner != nullptr ? owner->popError(status, L) : popMessage(L));
  }
  (void)callback;
}

void RfsmChart::refreshEvents(const statechart::StepEvents& events) {
  lua_State* L = lua_->get();
  struct Data {
    const RfsmChart* self;
    const statechart::StepEvents* events;
  } data{this, &events};
  detail::protectedCall(
      L,
      [](lua_State* S) -> int {
        const auto* d = static_cast<const Data*>(lua_touserdata(S, 1));
        lua_rawgeti(S, LUA_REGISTRYINDEX, d->self->description_ref_);
        lua_rawgeti(S, -1, kEvents);
        const auto count = static_cast<lua_Integer>(d->events->size());
        for (lua_Integer i = 0; i < count; ++i) {
          const std::string_view name = d->events->name(static_cast<std::size_t>(i));
          lua_pushlstring(S, name.data(), name.size());
          lua_rawseti(S, -2, i + 1);
        }
        for (lua_Integer i = count + 1; lua_rawgeti(S, -1, i) != LUA_TNIL; ++i) {
          lua_pop(S, 1);
          lua_pushnil(S);
          lua_rawseti(S, -2, i);
        }
        lua_pop(S, 1);
        return 0;
      },
      &data, 0);
}

statechart::DooStatus RfsmChart::resumeDoo(int node, bool restart) {
  lua_State* L = lua_->get();
  struct Data {
    const RfsmChart* self;
    int node;
    bool restart;
  } data{this, node, restart};
  // The coroutine of this state (a new one on restart), left on the main stack.
  detail::protectedCall(
      L,
      [](lua_State* S) -> int {
        const auto* d = static_cast<const Data*>(lua_touserdata(S, 1));
        lua_rawgeti(S, LUA_REGISTRYINDEX, d->self->description_ref_);
        lua_rawgeti(S, -1, kThreads);
        if (d->restart || lua_rawgeti(S, -1, d->node) != LUA_TTHREAD) {
          if (!d->restart) lua_pop(S, 1);
          lua_State* co = lua_newthread(S);
          lua_rawgeti(S, -3, kNodes);
          lua_rawgeti(S, -1, d->node);
          lua_rawgeti(S, -1, kNodeDoo);
          lua_xmove(S, co, 1);
          lua_pop(S, 2);
          lua_pushvalue(S, -1);
          lua_rawseti(S, -3, d->node);
        }
        return 1;
      },
      &data, 1);
  lua_State* co = lua_tothread(L, -1);
  // rFSM resumes with (fsm, state, 'doo') every time.
  lua_rawgeti(co, LUA_REGISTRYINDEX, description_ref_);
  lua_rawgeti(co, -1, kRoot);
  lua_rawgeti(co, -2, kNodes);
  lua_rawgeti(co, -1, node);
  lua_rawgeti(co, -1, kNodeTable);
  lua_replace(co, -3);
  lua_pop(co, 1);
  lua_rawgeti(co, -3, kWords);
  lua_rawgeti(co, -1, kDooWord);
  lua_replace(co, -2);
  lua_remove(co, -4);  // the description
  int results = 0;
  const int status = lua_resume(co, L, 3, &results);
  lua_pop(L, 1);  // the thread (kept in the description)
  if (status == LUA_YIELD) {
    const bool idle = results > 0 && lua_toboolean(co, -1);
    lua_pop(co, results);
    return idle ? DooStatus::Idle : DooStatus::Busy;
  }
  if (status == LUA_OK) {
    lua_pop(co, results);
    return DooStatus::Done;
  }
  LuaState* owner = LuaState::from(co);
  std::string message = owner != nullptr ? owner->popError(status, co) : popMessage(co);
  throw std::runtime_error(message);
}

void RfsmChart::build() {
  lua_State* L = lua_->get();
  statechart::ChartBuilder builder;
  lua_rawgeti(L, LUA_REGISTRYINDEX, description_ref_);
  const int description = lua_gettop(L);

  auto action = [this](int node, int slot, int word) -> statechart::Action {
    pushSlot(kNodes, node, slot);
    const bool present = lua_isfunction(lua_->get(), -1);
    lua_pop(lua_->get(), 1);
    if (!present) return {};
    return [this, node, slot, word] {
      lua_State* S = lua_->get();
      pushSlot(kNodes, node, slot);
      pushDescriptionField(S, description_ref_, kRoot);
      pushSlot(kNodes, node, kNodeTable);
      pushWord(S, description_ref_, word);
      callLua(3, "");
      lua_pop(S, 1);
    };
  };

  lua_rawgeti(L, description, kNodes);
  const auto node_count = static_cast<int>(lua_rawlen(L, -1));
  lua_pop(L, 1);
  for (int i = 1; i <= node_count; ++i) {
    pushSlot(kNodes, i, kNodeKind);
    const std::string kind = stringAt(L, -1);
    pushSlot(kNodes, i, kNodeParent);
    const std::string parent = stringAt(L, -1);
    pushSlot(kNodes, i, kNodeName);
    const std::string name = stringAt(L, -1);
    pushSlot(kNodes, i, kNodeOrigin);
    const std::string origin = stringAt(L, -1);
    pushSlot(kNodes, i, kNodeDoo);
    const bool has_doo = lua_isfunction(L, -1);
    lua_pop(L, 5);
    if (kind == "conn") {
      builder.addConnector(parent, name, origin);
      continue;
    }
    statechart::StateSpec spec;
    spec.entry = action(i, kNodeEntry, kEntryWord);
    spec.exit = action(i, kNodeExit, kExitWord);
    if (has_doo) spec.doo = [this, i](bool restart) { return resumeDoo(i, restart); };
    spec.origin = origin;
    try {
      builder.addState(parent, name, std::move(spec));
    } catch (const std::invalid_argument& e) {
      lua_settop(L, description - 1);
      throw core::Error(e.what());
    }
  }

  lua_rawgeti(L, description, kTransitions);
  const auto transition_count = static_cast<int>(lua_rawlen(L, -1));
  lua_pop(L, 1);
  for (int j = 1; j <= transition_count; ++j) {
    statechart::TransitionSpec spec;
    pushSlot(kTransitions, j, kScope);
    const std::string scope = stringAt(L, -1);
    pushSlot(kTransitions, j, kSrc);
    spec.src = stringAt(L, -1);
    pushSlot(kTransitions, j, kTgt);
    spec.tgt = stringAt(L, -1);
    pushSlot(kTransitions, j, kPn);
    spec.pn = static_cast<int>(lua_tointeger(L, -1));
    pushSlot(kTransitions, j, kTransitionOrigin);
    spec.origin = stringAt(L, -1);
    pushSlot(kTransitions, j, kEventList);
    for (lua_Integer k = 1; lua_rawgeti(L, -1, k) == LUA_TSTRING; ++k) {
      spec.events.push_back(stringAt(L, -1));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    pushSlot(kTransitions, j, kGuard);
    const bool has_guard = lua_isfunction(L, -1);
    pushSlot(kTransitions, j, kEffect);
    const bool has_effect = lua_isfunction(L, -1);
    lua_pop(L, 8);
    if (has_guard)
      spec.guard = [this, j](const statechart::StepEvents& events) {
        lua_State* S = lua_->get();
        refreshEvents(events);
        pushSlot(kTransitions, j, kGuard);
        pushSlot(kTransitions, j, kTransitionTable);
        pushDescriptionField(S, description_ref_, kEvents);
        callLua(2, "guard");
        const bool refused = lua_isboolean(S, -1) && !lua_toboolean(S, -1);  // rFSM: only false refuses
        lua_pop(S, 1);
        return !refused;
      };
    if (has_effect)
      spec.effect = [this, j](const statechart::StepEvents& events) {
        lua_State* S = lua_->get();
        refreshEvents(events);
        pushSlot(kTransitions, j, kEffect);
        pushDescriptionField(S, description_ref_, kRoot);
        pushSlot(kTransitions, j, kTransitionTable);
        pushWord(S, description_ref_, kEffectWord);
        pushDescriptionField(S, description_ref_, kEvents);
        callLua(4, "effect");
        lua_pop(S, 1);
      };
    builder.addTransition(scope, std::move(spec));
  }

  // The root's own entry and exit (rare, but rFSM allows them).
  lua_rawgeti(L, description, kRootCallbacks);
  statechart::StateSpec root;
  for (int k = 1; k <= 2; ++k) {
    if (lua_rawgeti(L, -1, k) == LUA_TFUNCTION) {
      const int word = k == 1 ? kEntryWord : kExitWord;
      (k == 1 ? root.entry : root.exit) = [this, k, word] {
        lua_State* S = lua_->get();
        lua_rawgeti(S, LUA_REGISTRYINDEX, description_ref_);
        lua_rawgeti(S, -1, kRootCallbacks);
        lua_rawgeti(S, -1, k);
        lua_rawgeti(S, -3, kRoot);
        lua_pushvalue(S, -1);
        lua_rawgeti(S, -5, kWords);
        lua_rawgeti(S, -1, word);
        lua_replace(S, -2);
        callLua(3, "");
        lua_pop(S, 3);
      };
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 2);  // root callbacks, description
  builder.setRootCallbacks(std::move(root));
  try {
    chart_ = builder.build();
  } catch (const std::invalid_argument& e) {
    throw core::Error(e.what());
  }
}

}  // namespace cobra::script
