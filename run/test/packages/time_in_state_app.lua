-- The runner's test application (../apps/threshold/threshold.lua) with an observer of a package:
-- the package cobra_time_in_state (time_in_state.cpp) adds the `run` table's section
-- `time_in_state`, which this run uses (observer_package_test.cpp).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
packages_list = { "cobra_signal", "cobra_coordination", "cobra_time_in_state" }
initConfigurator(packages_list, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "Gain", component_type = "Gain" },
  { peer_name = "Detector", component_type = "ThresholdDetector" },
  { peer_name = "Recorder", component_type = "Recorder" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
}, "")
getReferences()
Sine.frequency = 1        -- Hz
Sine.amplitude = 1
Gain.k = 1
Detector.threshold = 0.9
Detector.hysteresis = 0.05
TaskSup.fsm_path = here .. "../apps/threshold/threshold_task.lua"
setActivities({
  { peer_name = "Sine", period = 0.001 },
  { peer_name = "Gain", period = 0 },
  { peer_name = "Detector", period = 0 },
  { peer_name = "Recorder", period = 0 },
  { peer_name = "TaskSup", period = 0.01 },
})
connectPorts({
  { output = "Sine.out", input = "Gain.in" },
  { output = "Gain.out", input = "Detector.in" },
  { output = "Gain.out", input = "Recorder.in", conn_policy = { type = "buffer", size = 16 } },
  { output = "Detector.events", input = "TaskSup.inputEvents", conn_policy = { type = "buffer", size = 16 } },
})
local all = { "Sine", "Gain", "Detector", "Recorder", "TaskSup" }
configureComponents(all)
startComponents(all)

run = {
  title = "Threshold test application with a package's observer",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
  summary = { { name = "threshold crossings", count = { "e_above_threshold" } } },
  time_in_state = { chart = "task" },
}
