-- A run that switches deployments after setup, for the editor's running view
-- (studio/test/editor_test.cpp): the task chart (editor_switch_task.lua) asks the deployment
-- supervisor for "first" (GainA between Sine and Recorder), 20 ms later for "second" (GainB in its
-- place), and is done 20 ms after that.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local charts = here .. "../../../components/coordination/charts/"
packages_list = { "cobra_signal", "cobra_coordination" }
initConfigurator(packages_list, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "GainA", component_type = "Gain" },
  { peer_name = "GainB", component_type = "Gain" },
  { peer_name = "Recorder", component_type = "Recorder" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
  { peer_name = "DepSup", component_type = "Supervisor" },
}, "")
getReferences()
GainB.k = 3
TaskSup.fsm_path = here .. "editor_switch_task.lua"
DepSup.fsm_path = charts .. "deployment_supervisor.lua"
setActivities({
  { peer_name = "Sine", period = 0.001 },
  { peer_name = "TaskSup", period = 0.001 },
  { peer_name = "DepSup", period = 0.001 },
})
local buffered = { type = "buffer", size = 16 }
connectPorts({
  { output = "TaskSup.outputEvents", input = "DepSup.inputEvents", conn_policy = buffered },
  { output = "DepSup.outputEvents", input = "TaskSup.inputEvents", conn_policy = buffered },
})
local always = { "Sine", "Recorder", "TaskSup", "DepSup" }
configureComponents(always)
startComponents(always)
defineDeployment("first", { components = { "GainA" }, connections = {
  { output = "Sine.out", input = "GainA.in" }, { output = "GainA.out", input = "Recorder.in" } } })
defineDeployment("second", { components = { "GainB" }, connections = {
  { output = "Sine.out", input = "GainB.in" }, { output = "GainB.out", input = "Recorder.in" } } })

run = {
  title = "editor: deployments switched during the run",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
}
