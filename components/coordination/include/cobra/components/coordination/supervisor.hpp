#pragma once
/// @file
/// The Supervisor component (thesis §4.5.10, ARCHITECTURE §5): a Supervision component that runs one
/// rFSM chart. Task, deployment and configuration supervisors (Fig. 2.6) are three instances of
/// it with different charts.

#include <atomic>
#include <memory>
#include <string>

#include "cobra/core/bounded_string.hpp"
#include "cobra/core/component.hpp"
#include "cobra/deploy/configurator_client.hpp"
#include "cobra/script/lua_state.hpp"
#include "cobra/script/rfsm.hpp"
#include "cobra/statechart/machine.hpp"

namespace cobra::components {

/// Interface:
/// - property `fsm_path`: the rFSM chart file (`return rfsm.state{ ... }`); its folder is on the
///   chart's package.path, so a chart can `require` helpers next to it; `lua_pool_size` (B): the
///   chart's Lua memory, reserved at configure (0: unbounded); `max_steps` per update;
/// - ports `inputEvents` (event port: an event named N from component S reaches the chart as two
///   events of the same step, N and N@S, unless N already has an @), `outputEvents`, and
///   `taskState` (TaskState: the active leaf's full path, written when it changes).
///
/// In the chart's Lua code (besides the `rfsm` module): `emit(name)` writes an event on
/// outputEvents; `raise(name)` queues an event for the chart itself; `applyDeployment(name)` and
/// `applyConfiguration(name)` ask the Configurator that made this component for a switch (true if
/// queued), answered by the events `e_deployment_done@<name>` / `e_deployment_failed@<name>` and
/// `e_configuration_done@<name>` / `e_configuration_failed@<name>`; `self` is this component and
/// each peer (addPeers) is a global under its name, with everything script/bindings.hpp gives
/// (`TrajGen:askStartMove()`, `Planner.min_distance`, ...).
///
/// The chart is stepped until idle (rfsm.run) on every update: when events arrive (inputEvents is
/// an event port) and at every period of a periodic activity (for doo and time events, which use
/// this component's clock: simulated on the lockstep clock). Real time: stepping, emit, raise and
/// the switch requests allocate nothing from the system once configured (Lua's own allocations
/// come from the pool).
///
/// Failures: a chart callback (entry, doo, exit, guard, effect) that raises a Lua error, or the
/// chart's Lua code running past `lua_budget` s of CPU time in one update (an endless loop), ends
/// the update at once: the component goes to Exception (core emits `e_exception@<name>`) with
/// the callback, the element and the user's file:line in its lastError, e.g. "component
/// 'TaskSup': updateHook threw: entry of root.Moving failed: task.lua:12: attempt to call a nil
/// value (global 'stopp')"; the failure is also printed and counted in `chart_errors`. Loading
/// the chart (its top-level code) has `lua_load_budget` s. When the component enters Exception,
/// the chart's global function `exceptionHook`, if the chart file defines one, runs once (with
/// the step budget) so the task can leave its robots safe (stop the motion: the admittances hold
/// them); its own failure is printed. A pending interrupt (script::LuaState::watchInterrupt:
/// Ctrl-C, SIGTERM) also ends a chart step stuck in a loop, the same way.
class Supervisor : public core::Component, public deploy::ConfiguratorClient {
 public:
  explicit Supervisor(std::string name);
  ~Supervisor() override;

  /// The chart's active leaf ("" before start). From the component's thread or when not running.
  std::string_view activeState() const;
  /// The loaded chart (immutable until the next configure), e.g. for statechart::describe;
  /// nullptr before configure.
  const statechart::Chart* chart() const noexcept;
  /// The configuration the Configurator last applied at this supervisor's request ("" none): an
  /// observer sees each supervisor's own even when two are applied between two of its looks.
  /// From the component's thread or, on the lockstep clock, between two instants.
  std::string_view lastConfiguration() const noexcept { return last_configuration_.view(); }

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;
  void exceptionHook() override;
  void onRequestDone(const deploy::SwitchRequest& request, bool ok, std::string_view message) override;

 private:
  friend struct SupervisorLua;
  void publishState() noexcept;
  /// Steps the chart until idle, `max_steps` or a failing callback; throws the first failure
  /// (core::Error naming the callback, element and file:line), once the step is over.
  void runChart();
  void emitChartEvent(std::string_view name) noexcept;
  /// Raises `a` followed by `b` (b may be empty) as one event name, without allocating.
  void raiseJoined(std::string_view a, std::string_view b) noexcept;

  core::Property<std::string> fsm_path_{"fsm_path", "", "", "rFSM chart file (return rfsm.state{ ... })"};
  core::Property<int> pool_size_{"lua_pool_size", 512 * 1024, "B",
                                 "Lua memory of the chart, reserved at configure; 0 = unbounded (not real-time)"};
  core::Property<int> max_steps_{"max_steps", 1000, "1", "most chart steps per update (a busy doo stops there)"};
  core::Property<int> chart_errors_{"chart_errors", 0, "1", "chart callbacks that failed since configure"};
  core::Property<double> budget_{"lua_budget", 0.005, "s",
                                 "CPU time the chart's Lua code may take in one update (start, events, doo, time "
                                 "events); past it the component goes to Exception naming the file:line; 0 = none"};
  core::Property<double> load_budget_{"lua_load_budget", 1.0, "s",
                                      "CPU time the chart file's top-level code may take when it is loaded at "
                                      "configure; 0 = none"};

  core::InputPort<core::Event> input_events_{"inputEvents", "events for the chart (from components and supervisors)", ""};
  core::OutputPort<core::Event> output_events_{"outputEvents", "events the chart emits", ""};
  core::OutputPort<core::TaskState> task_state_{"taskState", "the chart's active state (full path)", ""};
  /// The Configurator's answers, written by its thread into inputEvents (not a port of the interface).
  core::OutputPort<core::Event> answers_{"supervisor_answers", "answers to switch requests", ""};

  std::unique_ptr<script::LuaState> lua_;
  std::unique_ptr<script::RfsmChart> chart_;
  std::unique_ptr<statechart::Machine> machine_;
  std::unique_ptr<statechart::Observer> observer_;
  const char* published_ = nullptr;  // the leaf last written on taskState
  core::BoundedString<63> last_configuration_;  // written by onRequestDone (the Configurator's side)
};

}  // namespace cobra::components
