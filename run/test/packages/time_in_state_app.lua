-- The runner's test application (../apps/threshold/threshold.lua) with an observer of a package:
-- the package cobra_time_in_state (time_in_state.cpp) adds the `run` table's section
-- `time_in_state`, which this run uses (observer_package_test.cpp).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
packages_list = { "cobra_signal", "cobra_coordination", "cobra_time_in_state" }
dofile(here .. "../apps/threshold/threshold.lua")

run = {
  title = "Threshold test application with a package's observer",
  charts = { { name = "task", supervisor = "TaskSup", done = "root.done" } },
  summary = { { name = "threshold crossings", count = { "e_above_threshold" } } },
  time_in_state = { chart = "task" },
}
