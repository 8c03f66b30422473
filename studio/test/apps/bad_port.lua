-- A studio table naming a port the deployment does not have (studio/test/bridge_test.cpp).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "../../../run/test/apps/threshold/threshold.lua")
run.studio = {
  signals = { "Sine.out",
              "Gain.outt" },
}
