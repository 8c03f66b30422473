-- A one-chart application with a component that fails at 50 ms (run/test/runner_test.cpp
-- registers its type, Overheating, through RunOptions::add_packages).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
initConfigurator({ "cobra_coordination", "run_test" }, {
  { peer_name = "Heater", component_type = "Overheating" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
}, "")
getReferences()
TaskSup.fsm_path = here .. "threshold_task.lua"
setActivities({ { peer_name = "Heater", period = 0.001 }, { peer_name = "TaskSup", period = 0.01 } })
configureComponents({ "Heater", "TaskSup" })
startComponents({ "Heater", "TaskSup" })
run = { charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } } }
