-- The take-over in the tissue (take_over_in_tissue.lua) with the Leap Motion: the surgeon's right
-- hand, 20 cm above the device (the simulator's scripted hand, LeapSim.right_hand, m).
-- The Leap renders no force (its side's Passivity layer renders and pays nothing): the master's
-- wrench as it arrives over the link (NeedleLink.linkedSlaveWrench) is what a haptic device would
-- be given.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
return dofile(here .. "take_over_in_tissue.lua")("LeapSim.right_hand", { 0.050, 0, 0.2 })
