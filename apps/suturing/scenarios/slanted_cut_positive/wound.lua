-- The slanted scenario's mirror: the same 36 mm cut, 5 mm open, 3 stitches, slanted +15 degrees
-- from the world's x axis (towards the stick's side as it goes on) instead of -15: the slanted
-- scenario's cut mirrored about x. Before each half the stick goes aside in the stitch's frame
-- (state_table.txt, MoveOverWound): held where it pushed the last thread, it kept that half's
-- direction while the platform turned, and the two upper arms came within 1.3 mm of each other.
-- The closest of the four scenarios (4.85 mm, the two upper arms as the stick starts its push).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local wound = dofile(here .. "../slanted_cut/wound.lua")
for i = 2, #wound.cut, 2 do wound.cut[i] = -wound.cut[i] end  -- y -> -y
return wound
