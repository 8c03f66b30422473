-- The test application recording a port its Gain does not have.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "threshold.lua")
run.record.ports = { "Sine.out",
  "Gain.outt" }
