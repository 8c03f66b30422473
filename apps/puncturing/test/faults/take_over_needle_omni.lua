-- The take-over in the tissue (take_over_in_tissue.lua) with the Phantom Omni: the stylus's
-- displacement from where the hand holds it (hand_motion, m).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
return dofile(here .. "take_over_in_tissue.lua")("NeedleOmni.hand_motion", { 0, 0, 0 })
