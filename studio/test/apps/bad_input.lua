-- A studio input calling an operation the component does not have (studio/test/bridge_test.cpp).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "../../../run/test/apps/threshold/threshold.lua")
run.studio = {
  inputs = {
    clear = { "Recorder.clean" },
  },
}
