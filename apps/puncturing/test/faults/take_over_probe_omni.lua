-- The take-over on the skin (take_over_on_skin.lua) with the probe robot's Phantom Omni: the
-- stylus's displacement from where the hand holds it (hand_motion, m).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
return dofile(here .. "take_over_on_skin.lua")("ProbeOmni.hand_motion", { 0, 0, 0 })
