-- The test application with a port of a type the recorder does not take (an Event port).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "threshold.lua")
run.record.ports = { "Sine.out",
  "Detector.events" }
