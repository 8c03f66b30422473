-- A small application for the runner's tests (run/test/runner_test.cpp): a 1 Hz sine through a
-- gain into a threshold detector whose events drive a one-chart task. With k = 1 the sine passes
-- 0.9 at 0.18 s and falls back under 0.85 (threshold - hysteresis) at about 0.33 s: the task is done.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
-- An application that runs this file (dofile) may name its packages first (more observers).
packages_list = packages_list or { "cobra_signal", "cobra_coordination" }
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
TaskSup.fsm_path = here .. "threshold_task.lua"
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
  title = "Threshold test application",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
  record = { period = 0.01, ports = { "Sine.out", "Gain.out" } },
  plots = { { title = "The signal and its gain", unit = "1", series = { "Sine.out", "Gain.out" } } },
  summary = {
    { name = "threshold crossings", count = { "e_above_threshold" } },
    { name = "signal when high", port = "Gain.out", on_enter = "task:root.high" },
  },
}
