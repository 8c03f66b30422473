-- The test application with a studio input calling an operation of no component: the run's
-- constructor refuses it after it listens to the components' state changes (they are running).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "threshold.lua")
run.studio = {
  inputs = { go = { "Nobody.say", "e_go" } },
}
