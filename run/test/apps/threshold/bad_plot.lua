-- The test application plotting a port of a type the plots do not take.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "threshold.lua")
run.plots = {
  { title = "events", series = { "TaskSup.outputEvents" } },
}
