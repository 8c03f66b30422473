-- The runner's test application (run/test/apps/threshold) with a studio table: a plotted signal
-- and one input (studio/test/bridge_test.cpp).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "../../../run/test/apps/threshold/threshold.lua")
run.studio = {
  signals = { "Sine.out", "Gain.out" },
  inputs = { clear_recorder = { "Recorder.clear", label = "Clear the recorder" } },
}
