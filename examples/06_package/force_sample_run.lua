-- Example 06's type in a run of `cobra run`: the filter's `sample_out`, an example.ForceSample
-- (a record of the package, registered with cobra::types::registerType<T>()), is recorded in the
-- run's signals.csv one column per field with its unit (Filter.sample_out.force [N],
-- Filter.sample_out.filtered [N], Filter.sample_out.count), plotted in report.html by its fields,
-- and drawn by cobra studio as a signal (Filter.sample_out.filtered, N). The task is done after
-- 1 s of a 10 N step filtered at 0.5 Hz.
--   cobra run force_sample_run.lua --report DIR      (DIR/signals.csv, DIR/report.html, DIR/studio/)
--   cobra run force_sample_run.lua --studio          (the filtered force live in the browser)
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
packages_list = { "cobra_signal", "cobra_coordination", "example_filters" }
components_list = {
  { peer_name = "Force", component_type = "Constant" },
  { peer_name = "Filter", component_type = "ForceLowPass" },
  { peer_name = "TaskSup", component_type = "Supervisor" },
}
initConfigurator(packages_list, components_list)
getReferences()

Force.value = 10.0             -- N
Filter.cutoff_frequency = 0.5  -- Hz
Filter.initial_force = 0.0     -- N
TaskSup.fsm_path = here .. "force_sample_task.lua"

setActivities({
  { peer_name = "Force", period = 0.001 },
  { peer_name = "Filter", period = 0.001 },
  { peer_name = "TaskSup", period = 0.001 },
})
connectPorts({ { output = "Force.out", input = "Filter.force_in", conn_policy = rtt.Variable("ConnPolicy") } })
local all = { "Force", "Filter", "TaskSup" }
configureComponents(all)
startComponents(all)

run = {
  title = "example.ForceSample recorded and plotted",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
  record = { period = 0.1, ports = { "Filter.sample_out" } },  -- s: a row every 100 ms
  plots = { { title = "The filter's samples: the force read and the force written", unit = "N",
              series = { "Filter.sample_out.force", "Filter.sample_out.filtered" } } },
  studio = { signals = { "Filter.sample_out.filtered" } },
}
