-- A run whose task chart gets stuck in an endless loop (stuck_task.lua) with its Lua budget off
-- (lua_budget = 0), so that only an interrupt can end it: run_interrupt_test.sh sends SIGTERM and
-- expects the run to end through its clean path, on the lockstep clock and on the wall clock.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
initConfigurator({ "cobra_signal", "cobra_coordination" }, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
}, "")
getReferences()
TaskSup.fsm_path = here .. "stuck_task.lua"
TaskSup.lua_budget = 0  -- s: no budget
setActivities({ { peer_name = "Sine", period = 0.001 }, { peer_name = "TaskSup", period = 0.001 } })
configureComponents({ "Sine", "TaskSup" })
startComponents({ "Sine", "TaskSup" })

run = {
  title = "a chart stuck in a loop",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
}
