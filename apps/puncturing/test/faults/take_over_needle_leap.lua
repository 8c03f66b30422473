-- The take-over in the tissue (take_over_in_tissue.lua) with the Leap Motion: the surgeon's right
-- hand, 20 cm above the device (the simulator's scripted hand, LeapSim.right_hand, m).
-- The Leap renders no force: the force the coupling computes for the master
-- (NeedlePassivity.masterForce) is what a haptic device would render.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
return dofile(here .. "take_over_in_tissue.lua")("LeapSim.right_hand", { 0.050, 0, 0.2 })
