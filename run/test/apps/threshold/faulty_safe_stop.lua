-- faulty.lua's component that fails at 50 ms (Overheating, registered by run/test/runner_test.cpp)
-- under a chart with a safe stop: the runner tells it e_component_error (source: Heater), and the
-- chart stops safely (faulty_task.lua). With `deaf = true` set before this file (RunOptions::
-- before_lua) the chart hears nothing of it (faulty_deaf_task.lua): the component error stands.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
initConfigurator({ "cobra_coordination", "run_test" }, {
  { peer_name = "Heater", component_type = "Overheating" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
}, "")
getReferences()
TaskSup.fsm_path = here .. (deaf and "faulty_deaf_task.lua" or "faulty_task.lua")
setActivities({ { peer_name = "Heater", period = 0.001 }, { peer_name = "TaskSup", period = 0.01 } })
configureComponents({ "Heater", "TaskSup" })
startComponents({ "Heater", "TaskSup" })
run = {
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done", safe_stop = "root.stopped" } },
  failures = { "e_component_error" },
}
