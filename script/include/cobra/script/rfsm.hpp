#pragma once
/// @file
/// rFSM charts (`return rfsm.state{ ... }`, thesis §3.1.3) loaded unchanged into cobra's C++
/// statechart engine, with their entry/exit/doo/guard/effect functions run in Lua.
///
/// `installRfsm(lua)` gives a Lua state the module `rfsm` (also `require("rfsm")`): the model
/// constructors `state`/`sista`/`csta`/`simple_state`/`composite_state`, `conn`/`connector`,
/// `trans`/`transition`, `yield` (coroutine.yield), `load(file)`, the predicates `is_state`,
/// `is_conn`, `is_trans`, `is_node`, `is_leaf`, `is_composite`, and the operational functions
/// `init(model)`, `step(fsm, n)`, `run(fsm)`, `send_events(fsm, ...)`, `get_actleaf_fqn(fsm)`,
/// `get_active_conf(fsm)`, `reset(fsm)`, `pre_step_hook_add`/`post_step_hook_add` and the
/// `fsm.getevents` hook, so Lua scripts written to drive rFSM work unchanged. `rfsm_timeevent`
/// (`require`) has `set_gettime_hook` for the machines `init` makes from then on.
///
/// Callbacks get rFSM's arguments: entry/exit/doo `(fsm, state, 'entry'|'exit'|'doo')`,
/// guard `(transition, events)`, effect `(fsm, transition, 'effect', events)`; `events` is a list
/// of the step's event names; a `doo` runs as a coroutine resumed once per step, idle when it
/// yields true. A failing Lua callback is reported (as rFSM prints it) and the step goes on.
///
/// Load errors name the file and line of the element (where its constructor was called) and its
/// path: "task.lua:12: transition in root.on has no tgt (its fields: events, src, tqt)".

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "cobra/script/lua_state.hpp"
#include "cobra/statechart/chart.hpp"
#include "cobra/statechart/machine.hpp"

namespace cobra::script {

/// Defines the global `rfsm` and the modules "rfsm" and "rfsm_timeevent" in `lua`.
/// @throws cobra::core::Error when the Lua state runs out of memory.
void installRfsm(LuaState& lua);

/// A chart loaded from an rFSM model, with the Lua functions it calls. It must outlive its
/// machines and be used from the thread that uses `lua`.
class RfsmChart {
 public:
  /// Runs the file (it must return an rFSM state) and builds its chart. Installs `rfsm` first
  /// when needed. @throws cobra::core::Error naming the file and line of what is wrong.
  static std::unique_ptr<RfsmChart> loadFile(LuaState& lua, const std::string& path);
  /// Same for Lua source; `chunk_name` appears in messages ("=task", "@task.lua").
  static std::unique_ptr<RfsmChart> loadString(LuaState& lua, const std::string& code, const std::string& chunk_name);
  ~RfsmChart();
  RfsmChart(const RfsmChart&) = delete;
  RfsmChart& operator=(const RfsmChart&) = delete;

  const statechart::Chart& chart() const { return chart_; }
  /// Where `rfsm.send_events(fsm, ...)` from this chart's functions raises events (nullptr: dropped).
  void bind(statechart::Machine* machine);

 private:
  RfsmChart(LuaState& lua, int description_ref);
  void build();
  /// Pushes field `slot` of entry `index` of list `list` (1 nodes, 2 transitions) of the description.
  void pushSlot(int list, int index, int slot) const;
  void callLua(int arguments, const char* callback) const;
  void refreshEvents(const statechart::StepEvents& events);
  statechart::DooStatus resumeDoo(int node, bool restart);

  LuaState* lua_;
  int description_ref_;
  statechart::Chart chart_;
  friend struct RfsmAccess;
};

}  // namespace cobra::script
