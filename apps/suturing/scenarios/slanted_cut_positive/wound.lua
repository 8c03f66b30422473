-- The slanted scenario's mirror: the same 36 mm cut slanted +15 degrees from the world's x axis
-- (towards the stick's side as it goes on), 5 mm open at its middle, 3 stitches. The stick goes
-- over each half's push point before it (state_table.txt, MoveOverWound): held where it pushed the
-- last thread, it kept that half's direction while the platform turned, and the two upper arms came
-- within 1.3 mm of each other. Same fields as straight_cut/wound.lua.
local a = math.rad(15)
local h = 0.018
return {
  cut = { -h * math.cos(a), -h * math.sin(a), h * math.cos(a), h * math.sin(a) },
  wound_pose = { 0.178, 0.0, 0.06, 0, 0, 0, 1 },
  max_gap = 0.005,
  closed_gap = 0.0005,
  stitches = 3,
}
