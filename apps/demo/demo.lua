-- cobra's basic demo, as files run by `cobra run apps/demo` (what `./do demo basics` shows first):
--
--   SineGenerator (1 kHz) --out-> Gain --out-> Recorder
--                                      \-> ThresholdDetector --events-> TaskSup (demo_task.lua)
--
-- A 50 Hz sine times k = 2 crosses the detector's threshold (1.5) and falls back under it; 20 ms
-- later the task chart is done. At 20 ms the gain is set to 0.5 while running (a property change,
-- applied between two updates; the run table's action): the detector never fires again.
-- `cobra describe apps/demo/demo.lua` prints the components' interfaces, `cobra graph
-- apps/demo/demo.lua -o demo.svg` draws the deployment.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
packages_list = { "cobra_signal", "cobra_coordination" }
initConfigurator(packages_list, {
  { peer_name = "Sine", component_type = "SineGenerator" },
  { peer_name = "Gain", component_type = "Gain" },
  { peer_name = "Recorder", component_type = "Recorder" },
  { peer_name = "Detector", component_type = "ThresholdDetector" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
}, "")
getReferences()
Sine.frequency = 50         -- Hz: one period every 20 ms
Sine.amplitude = 1
Gain.k = 2
Detector.threshold = 1.5
Detector.hysteresis = 0.2
TaskSup.fsm_path = here .. "demo_task.lua"
setActivities({
  { peer_name = "Sine", period = 0.001 },     -- periodic: 1 kHz in simulated time
  { peer_name = "Gain", period = 0 },         -- event-driven: runs when a sample arrives
  { peer_name = "Recorder", period = 0 },
  { peer_name = "Detector", period = 0 },
  { peer_name = "TaskSup", period = 0.001 },
})
local buffered = { type = "buffer", size = 16 }
connectPorts({
  { output = "Sine.out", input = "Gain.in" },
  { output = "Gain.out", input = "Recorder.in", conn_policy = buffered },
  { output = "Gain.out", input = "Detector.in", conn_policy = buffered },
  { output = "Detector.events", input = "TaskSup.inputEvents", conn_policy = buffered },
})
local all = { "Sine", "Gain", "Recorder", "Detector", "TaskSup" }
configureComponents(all)
startComponents(all)

run = {
  title = "cobra basic demo",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
  actions = { { on = { time = 0.02 }, set = { property = "Gain.k", value = 0.5 } } },
  record = { period = 0.001, ports = { "Sine.out", "Gain.out" } },
  plots = { { title = "The sine and the gain's output (k = 2, then 0.5 from 20 ms)", unit = "1",
              series = { "Sine.out", "Gain.out" } } },
  summary = { { name = "threshold crossings", count = { "e_above_threshold" } } },
}
